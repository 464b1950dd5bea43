#pragma once

// Frontiers onto enclosed unknown pockets (docs/architecture.md §5): the unknown behind
// furniture, in a cabinet's outline, in a shadow the robot drove past, or beyond a gap in
// a wall the robot cannot pass. Such a frontier can reveal little that the robot could
// enter, so ours leaves them to the end and then clears them nearest first.

#include <vector>

#include "common/occupancy_grid.h"
#include "frontier/frontier.h"
#include "navigation/costmap.h"

namespace aslam {

// For each frontier, the area (m^2) of the largest region of unknown cells the robot could
// enter (`costmap` traversable, 4-connected) that one of its cells touches (8-neighbours).
// Regions of at least `cap_m2`, and regions reaching the map's edge, are open: +infinity.
// A frontier touching no such cell (only a narrow gap, or the map moved on since it was
// extracted) gets 0. `costmap` is built from `map` with unknown_passable true.
std::vector<double> BorderedUnknownAreasM2(const OccupancyGrid& map, const Costmap& costmap,
                                           const std::vector<Frontier>& frontiers, double cap_m2);

}  // namespace aslam
