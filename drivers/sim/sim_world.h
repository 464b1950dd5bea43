#pragma once

// The simulator's ground-truth world: which cells are solid, circle
// collision and exact lidar ray casting on a static occupancy grid.

#include <cstdint>
#include <limits>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {
namespace internal {
struct Ray;  // a ray traversal's state (sim_world.cc)
}  // namespace internal

class SimWorld {
 public:
  // CastRay's result when nothing solid lies within max_range_m.
  static constexpr double kNoHit = std::numeric_limits<double>::infinity();

  // A cell is free iff its value is 0; occupied (1..100), unknown (-1) and
  // everything outside the map are solid. Aborts on an empty map.
  explicit SimWorld(const OccupancyGrid& map);

  const OccupancyGrid& map() const { return map_; }
  double resolution_m() const { return map_.resolution_m(); }
  // Total area of the free cells.
  double free_area_m2() const { return free_area_m2_; }

  bool IsSolid(CellIndex cell) const {
    return code_[PaddedIndex(cell.col, cell.row)] == kSolidCode;
  }
  bool IsSolidAt(Point2d point_m) const { return IsSolid(map_.WorldToCell(point_m)); }

  // True iff the open disc overlaps a solid cell (touching is not a collision).
  bool CircleCollides(Point2d center_m, double radius_m) const;

  // Distance from origin_m along the ray to the first solid cell boundary it
  // crosses, or kNoHit if that is farther than max_range_m. A ray starting in
  // a solid cell (or off the map) returns 0. Skips empty space with the
  // distance field; the result is bit-identical to CastRayPlain.
  double CastRay(Point2d origin_m, double angle_rad, double max_range_m) const;
  // Same with the direction as a unit vector (saves a sin/cos per beam).
  double CastRayAlong(Point2d origin_m, Point2d unit_direction, double max_range_m) const;
  // Reference Amanatides–Woo traversal visiting every cell: for tests.
  double CastRayPlain(Point2d origin_m, double angle_rad, double max_range_m) const;
  double CastRayAlongPlain(Point2d origin_m, Point2d unit_direction, double max_range_m) const;
  // CastRayAlong for many rays from one origin, bit-identical results. Rays
  // in sweep order (neighbours adjacent, as lidar beams) reuse each other's
  // free space and are about twice as fast as one at a time.
  std::vector<double> CastRays(Point2d origin_m, const std::vector<Point2d>& unit_directions,
                               double max_range_m) const;

  // A lower bound on the distance from any point of the cell to any solid
  // cell, in whole cells; -1 for a solid cell.
  int SafeSkipCells(CellIndex cell) const {
    const uint8_t code = code_[PaddedIndex(cell.col, cell.row)];
    return code == kSolidCode ? -1 : code;
  }

 private:
  static constexpr uint8_t kSolidCode = 255;

  // The padded grid has one solid ring around the map, so traversals need
  // no bounds checks; cells farther out are clamped onto that ring.
  std::size_t PaddedIndex(int col, int row) const;

  // Places a ray at its origin (direction still unset); false if it starts
  // in a solid cell or off the map, where every range is 0.
  bool PlaceRay(Point2d origin_m, double max_range_m, internal::Ray* ray) const;
  template <bool kUseDistanceField>
  double Cast(Point2d origin_m, Point2d unit_direction, double max_range_m) const;

  OccupancyGrid map_;
  double inverse_resolution_ = 0.0;  // multiplying is cheaper than dividing per ray
  int padded_width_ = 0;
  int padded_height_ = 0;
  double free_area_m2_ = 0.0;
  // Per padded cell: kSolidCode, or floor(clearance - sqrt(2) - margin) in
  // cells, capped below kSolidCode: a ray may advance that far without
  // entering a solid cell from anywhere in the cell.
  std::vector<uint8_t> code_;
};

}  // namespace aslam
