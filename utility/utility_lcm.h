#pragma once

// Translators between the utility's value types and its lcmtypes. FromLcm
// functions validate: nullopt means the message is to be dropped and counted.

#include <cstdint>
#include <optional>
#include <string>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/occupancy_grid.h"
#include "common/sensor_types.h"
#include "utility/goal_selector.h"

namespace aslam {

// UTILITY_SCORES for one decision.
utility_scores_t ScoresToLcm(const GoalDecision& decision, int64_t utime, int64_t decision_id,
                             UtilityMethod method, const Pose2d& robot, double compute_ms);

explore_goal_t GoalToLcm(int64_t utime, int64_t goal_id, Point2d target_m, int frontier_id);
explore_goal_t CancelToLcm(int64_t utime, int64_t goal_id);

enum class ExploreState { kWaiting, kExploring, kDone };
const char* ExploreStateName(ExploreState state);

struct ExploreStatus {
  int64_t utime = 0;
  ExploreState state = ExploreState::kWaiting;
  UtilityMethod method = UtilityMethod::kOurs;
  int64_t current_goal_id = -1;
  int num_frontiers = 0;
  int num_eligible = 0;
  int decisions = 0;
  int goals_reached = 0;
  int goals_failed = 0;
  std::string detail;
};
explore_status_t ToLcm(const ExploreStatus& status);

// The part of NAV_STATUS the utility acts on.
enum class NavGoalState { kIdle, kActive, kReached, kFailed, kUnreachable };
struct NavReport {
  int64_t utime = 0;
  int64_t goal_id = -1;
  NavGoalState state = NavGoalState::kIdle;
};
// Rejects unknown state or recovery codes, a goal id below -1 and non-finite numbers.
std::optional<NavReport> NavReportFromLcm(const nav_status_t& msg);

// SLAM_POSE and SLAM_MAP in the "map" frame; any other frame is rejected.
std::optional<StampedPose> MapFramePoseFromLcm(const pose_t& msg);
std::optional<OccupancyGrid> MapFrameGridFromLcm(const occupancy_grid_t& msg);

}  // namespace aslam
