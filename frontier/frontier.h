#pragma once

// A frontier as a value type: a segment of known-free cells bordering unknown
// space, with the reachable cell near its centroid the robot would drive to.
// FRONTIERS carries a list of them (frontier_lcm.h translates).

#include <cstdint>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {

struct Frontier {
  int id = 0;                     // stable across map updates while the frontier persists
  std::vector<CellIndex> cells;   // cells of the segment in the map it came from
  std::vector<Point2d> points_m;  // their centres, "map"
  Point2d centroid_m;
  Point2d target_m;  // reachable free cell near the centroid: the goal candidate
  int size_cells() const { return static_cast<int>(points_m.size()); }
};

struct FrontierList {
  int64_t utime = 0;
  int64_t map_revision = 0;  // revision of the SLAM_MAP they were extracted from
  std::vector<Frontier> frontiers;
};

}  // namespace aslam
