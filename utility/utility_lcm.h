#pragma once

// Translators from the utility's value types to its lcmtypes. The utility reads
// NAV_STATUS with navigation/nav_lcm.h and SLAM_POSE / SLAM_MAP with the "map"
// frame filter of common/types_lcm.h.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "aslam/explore_control_t.hpp"
#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/pose2d.h"
#include "utility/exploration_manager.h"
#include "utility/goal_selector.h"

namespace aslam {

// UTILITY_SCORES for one decision.
utility_scores_t ScoresToLcm(const GoalDecision& decision, int64_t utime, int64_t decision_id,
                             UtilityMethod method, const Pose2d& robot, double compute_ms);

// The terms of every frontier of a UTILITY_SCORES; nullopt for a count that disagrees with
// its array or an unknown eligibility code.
std::optional<std::vector<FrontierScore>> FrontierScoresFromLcm(const utility_scores_t& msg);

explore_goal_t ToLcm(const ExploreGoal& goal);
explore_status_t ToLcm(const ExploreStatus& status);
// nullopt for an unknown state or method.
std::optional<ExploreStatus> FromLcm(const explore_status_t& msg);
// explore_status_t's state code for `state`, and back (nullopt for an unknown code).
int8_t ExploreStateToLcm(ExploreState state);
std::optional<ExploreState> ExploreStateFromLcm(int8_t code);
// explore_control_t's command code for `command`, and back (nullopt for an unknown code).
int8_t ExploreCommandToLcm(ExploreCommand command);
std::optional<ExploreCommand> ExploreCommandFromLcm(int8_t code);
// An EXPLORE_CONTROL request from `source`, stamped with the wall clock.
explore_control_t ExploreControlMessage(ExploreCommand command, const std::string& source);

}  // namespace aslam
