#pragma once

// The global costmap built from a SLAM map (the ROS costmap_2d layering,
// simplified): occupied cells are lethal, cells within the robot radius plus
// a clearance margin of one are inscribed (impassable for the robot's
// centre: the margin is the DWA's safety margin, so the planner never routes
// through a gap the local planner refuses to drive through), and a decaying
// cost spreads over a further margin; unknown cells are passable at an extra
// cost, because frontier goals lie at the edge of the unknown. Distances come
// from OpenCV's distance transform (exact Euclidean, cell centre to the
// nearest obstacle cell's centre); unknown cells are not obstacles.
//
// Cost of a cell at obstacle distance d (metres):
//   d == 0                      kLethal
//   r = robot_radius + clearance_margin
//   0 < d <= r                  kInscribed
//   d <= r + inflation_margin   round((kInscribed - 1) * exp(-scale * (d - r)))
//   beyond                      kFree
// An unknown cell keeps this cost (cost() never includes the unknown penalty;
// the global planner adds options().unknown_cost itself), or reads kNoGo when
// unknown_passable is false.

#include <cstdint>
#include <vector>

#include "common/occupancy_grid.h"

namespace aslam {

struct CostmapOptions {
  double robot_radius_m = 0.20;
  double clearance_margin_m = 0.05;  // inscribed up to radius + this: keep equal to the DWA's safety_margin_m
  double inflation_margin_m = 0.40;  // decaying cost beyond the inscribed zone
  double cost_scaling_per_m = 5.0;   // cost = (kInscribed - 1) * exp(-scale * (d - radius))
  int occupied_threshold = 65;       // map cells >= this are obstacles (1..100)
  bool unknown_passable = true;
  int unknown_cost = 50;  // extra cost of entering an unknown cell, 0..252,
                          // on the same scale as cost() (see global_planner.h)

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

class Costmap {
 public:
  static constexpr uint8_t kFree = 0;
  static constexpr uint8_t kInscribed = 253;  // centre here = robot touches an obstacle
  static constexpr uint8_t kLethal = 254;     // an obstacle cell
  static constexpr uint8_t kNoGo = 255;       // unknown while unknown_passable is false

  Costmap() = default;
  // Throws std::invalid_argument for invalid options.
  Costmap(const OccupancyGrid& map, const CostmapOptions& options);
  // The same as *this = Costmap(map, options), reusing this costmap's layers
  // (not reallocated on a map of the same size). Throws like the constructor.
  void Rebuild(const OccupancyGrid& map, const CostmapOptions& options);

  int width_cells() const { return width_cells_; }
  int height_cells() const { return height_cells_; }
  double resolution_m() const { return resolution_m_; }
  Point2d origin_m() const { return origin_m_; }
  bool Contains(CellIndex cell) const {
    return cell.col >= 0 && cell.row >= 0 && cell.col < width_cells_ && cell.row < height_cells_;
  }
  std::size_t LinearIndex(CellIndex cell) const {
    return static_cast<std::size_t>(cell.row) * width_cells_ + cell.col;
  }
  CellIndex WorldToCell(Point2d point_m) const;
  Point2d CellCenter(CellIndex cell) const;

  // 0..254 as above (255 = never enter); off-map cells read kNoGo.
  uint8_t cost(CellIndex cell) const;
  // True when the robot's centre may be in this cell.
  bool Traversable(CellIndex cell) const { return cost(cell) < kInscribed; }
  bool IsUnknown(CellIndex cell) const;
  // Distance from the cell centre to the nearest obstacle cell centre, metres
  // (+inf when the map has no obstacle; 0 off the map).
  double ObstacleDistanceM(CellIndex cell) const;

  // Row-major raw layers (index LinearIndex(cell)), for tight loops.
  const std::vector<uint8_t>& costs() const { return costs_; }
  const std::vector<uint8_t>& unknown_mask() const { return unknown_; }  // 1 = unknown

  const CostmapOptions& options() const { return options_; }

 private:
  CostmapOptions options_;
  int width_cells_ = 0;
  int height_cells_ = 0;
  double resolution_m_ = 0.05;
  Point2d origin_m_;
  std::vector<uint8_t> costs_;
  std::vector<uint8_t> unknown_;
  std::vector<float> obstacle_distance_m_;
};

}  // namespace aslam
