#pragma once

// The global costmap built from a SLAM map (the ROS costmap_2d layering,
// simplified): occupied cells are lethal, cells within the robot radius plus
// a clearance margin of one's edge are inscribed (impassable for the robot's
// centre: the margin is the DWA's safety margin and the DWA measures to an
// obstacle cell's edge, so the planner never routes through a gap the local
// planner refuses to drive through), and a decaying
// cost spreads over a further margin; unknown cells are passable at an extra
// cost, because frontier goals lie at the edge of the unknown. Distances come
// from OpenCV's distance transform (exact Euclidean, cell centre to the
// nearest obstacle cell's centre); unknown cells are not obstacles.
//
// Cost of a cell at obstacle distance d (metres, centre to centre) and clearance
// c = d - resolution / 2 (to the obstacle cell's edge, as the DWA measures it):
//   d == 0                      kLethal
//   r = robot_radius + clearance_margin
//   0 < d, c <= r               kInscribed
//   c <= r + inflation_margin   round((kInscribed - 1) * exp(-scale * (c - r)))
//   beyond                      kFree
// An unknown cell keeps this cost (cost() never includes the unknown penalty;
// the global planner adds options().unknown_cost itself), or reads kNoGo when
// unknown_passable is false.
//
// Incremental updates (Update): a cell's cost depends only on the obstacles
// within r + inflation_margin of it, so when a new map has the same geometry
// (or only grew around the old one) and the options are unchanged, only the
// cells within that band of a cell whose obstacle status changed are
// recomputed, each from a distance transform over a window grown by the band
// again (so it sees every obstacle that can decide a recomputed cell). Costs,
// Traversable, IsUnknown and the raw layers are then bit-identical to a fresh
// Costmap(map, options); only ObstacleDistanceM may differ, and only beyond
// the band (see there).

#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"

namespace aslam {

struct CostmapOptions {
  double robot_radius_m = 0.20;
  double clearance_margin_m = 0.05;  // inscribed up to radius + this (robot.clearance_margin_m)
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

  // What Update did.
  enum class UpdateKind {
    kUnchanged,    // no cell changed obstacle or unknown status: nothing to do
    kIncremental,  // recomputed the band around the changed cells only
    kFull,         // Rebuild: options, resolution or a non-growing geometry changed,
                   // this costmap was empty, the map is over 2000 cells on a side,
                   // or the change was too large to pay off
  };
  // Brings this costmap to Costmap(map, options): afterwards cost(),
  // Traversable(), IsUnknown(), costs() and unknown_mask() equal a fresh
  // costmap's for every cell, whatever sequence of maps came before. Reuses
  // the previous result when the options are the same and the map has the
  // same resolution and either the same size and origin or grew around the
  // previous map by whole cells (the occupancy mapper's growth); otherwise
  // rebuilds. Distances beyond the cost band may then be stale (see
  // ObstacleDistanceM). Throws like the constructor.
  UpdateKind Update(const OccupancyGrid& map, const CostmapOptions& options);

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
  // (+inf when the map has no obstacle; 0 off the map). Exact after the
  // constructor, Rebuild, or an Update that rebuilt. After an incremental
  // Update it is exact (bit-identical to a fresh costmap's) wherever that
  // distance, as a float, is <= robot_radius_m + clearance_margin_m +
  // inflation_margin_m (also as a float: every cell whose cost is not kFree
  // for its distance); elsewhere it is some value above that bound -- the
  // earlier map's distance, an upper bound from a window, or +inf -- not
  // necessarily the current distance. Read distances beyond the band only
  // from a costmap that was built fresh.
  double ObstacleDistanceM(CellIndex cell) const;

  // Row-major raw layers (index LinearIndex(cell)), for tight loops.
  const std::vector<uint8_t>& costs() const { return costs_; }
  const std::vector<uint8_t>& unknown_mask() const { return unknown_; }  // 1 = unknown

  const CostmapOptions& options() const { return options_; }

 private:
  struct Box {  // cells [col0, col1) x [row0, row1)
    int col0, row0, col1, row1;
  };
  class CostFunction;  // cost of an obstacle distance (costmap.cc)

  // Cells (Chebyshev) beyond which an obstacle cannot change a cost.
  int BandCells() const;
  // Re-lays the layers onto `map`'s grid when it contains the current one at a
  // whole-cell offset, the new cells reading as unknown, obstacle-free and
  // far from obstacles, and adds to `boxes` the new cells within the band of
  // the old grid (where that distance may be wrong); false otherwise.
  bool GrowInto(const OccupancyGrid& map, std::vector<Box>* boxes);
  // Recomputes the distances and costs of the cells in `box` from `map`, with
  // a distance transform over `box` grown by `band` cells.
  void RecomputeBox(const OccupancyGrid& map, const Box& box, int band, CostFunction& cost);

  CostmapOptions options_;
  int width_cells_ = 0;
  int height_cells_ = 0;
  double resolution_m_ = 0.05;
  Point2d origin_m_;
  std::vector<uint8_t> costs_;
  std::vector<uint8_t> unknown_;
  std::vector<float> obstacle_distance_m_;
};

// The obstacles the navigator plans around beyond the map (NAV_OBSTACLES): the cells where the
// latest scan's returns near the robot fall and the map holds no obstacle, as centres in "map".
struct PlanningObstacles {
  int64_t utime = 0;  // when the navigator marked them
  std::vector<Point2d> points_m;
};

// `map` with the cells under `obstacles.points_m` occupied (points off the map are skipped):
// the map the navigator plans on, for a planner that must agree with it. nullopt when there
// is nothing to mark: no points, or points more than 10 s older than `utime` (the navigator
// sends them with every map at least, and SLAM re-announces an unchanged one every 5 s, so
// older ones come from a navigator gone quiet).
std::optional<OccupancyGrid> WithPlanningObstacles(const OccupancyGrid& map,
                                                   const PlanningObstacles& obstacles,
                                                   int64_t utime);

}  // namespace aslam
