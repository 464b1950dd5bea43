#pragma once

// Translators between the navigator's value types and its lcmtypes. FromLcm
// functions validate: nullopt means the message is to be dropped and counted.
// SLAM_POSE and SLAM_MAP go through the "map" frame filter of common/types_lcm.h.

#include <optional>
#include <string>
#include <vector>

#include "aslam/explore_goal_t.hpp"
#include "aslam/nav_obstacles_t.hpp"
#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "navigation/navigator.h"

namespace aslam {

// Rejects a negative goal id and (unless cancelling) a non-finite goal.
std::optional<NavGoalRequest> FromLcm(const explore_goal_t& msg);
explore_goal_t ToLcm(const NavGoalRequest& request);

// NAV_STATUS, for the navigator's own and for every listener (the utility, the harnesses):
// rejects unknown state or recovery codes, a goal id below -1 and a non-finite goal or distance.
nav_status_t ToLcm(const NavStatus& status);
std::optional<NavStatus> FromLcm(const nav_status_t& msg);

// NAV_OBSTACLES: rejects counts that disagree with the arrays and non-finite points.
nav_obstacles_t ToLcm(const PlanningObstacles& obstacles);
std::optional<PlanningObstacles> FromLcm(const nav_obstacles_t& msg);

nav_path_t PathToLcm(int64_t utime, int64_t goal_id, const std::vector<Point2d>& path_m,
                     double length_m);

}  // namespace aslam
