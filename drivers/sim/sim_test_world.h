#pragma once

// The simulator tests' world: a free interior [0, 10] x [0, 8] m inside one-cell walls, with
// a pillar at [6, 7] x [5, 6] so scans are not all alike.

#include "common/occupancy_grid.h"

namespace aslam {

inline OccupancyGrid RoomWithPillar() {
  OccupancyGrid grid(202, 162, 0.05, {-0.05, -0.05}, OccupancyGrid::kFree);
  for (int col = 0; col < 202; ++col) grid.at({col, 0}) = grid.at({col, 161}) = 100;
  for (int row = 0; row < 162; ++row) grid.at({0, row}) = grid.at({201, row}) = 100;
  for (int row = 101; row < 121; ++row) {
    for (int col = 121; col < 141; ++col) grid.at({col, row}) = 100;
  }
  return grid;
}

}  // namespace aslam
