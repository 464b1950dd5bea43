#pragma once

// Translators between the navigator's value types and its lcmtypes. FromLcm
// functions validate: nullopt means the message is to be dropped and counted.

#include <optional>
#include <string>
#include <vector>

#include "aslam/explore_goal_t.hpp"
#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/occupancy_grid.h"
#include "common/sensor_types.h"
#include "navigation/navigator.h"

namespace aslam {

// The navigator works in "map": any other frame is rejected, as are a
// negative goal id and (unless cancelling) a non-finite goal.
std::optional<NavGoalRequest> FromLcm(const explore_goal_t& msg);
explore_goal_t ToLcm(const NavGoalRequest& request);

std::optional<StampedPose> MapPoseFromLcm(const pose_t& msg);
std::optional<OccupancyGrid> MapFromLcm(const occupancy_grid_t& msg);

nav_status_t ToLcm(const NavStatus& status);
// Rejects unknown state or recovery codes and a non-finite goal or distance.
std::optional<NavStatus> FromLcm(const nav_status_t& msg);

nav_path_t PathToLcm(int64_t utime, int64_t goal_id, const std::vector<Point2d>& path_m,
                     double length_m);

}  // namespace aslam
