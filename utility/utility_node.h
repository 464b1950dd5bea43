#pragma once

// The utility on LCM: subscribes FRONTIERS, POSE_GRAPH, SLAM_MAP, SLAM_POSE,
// NAV_STATUS, NAV_OBSTACLES and EXPLORE_CONTROL; hands them to the ExplorationManager (when to
// decide, goal ids, blacklist, resends, cancels, done: docs/architecture.md §9), runs the
// GoalSelector when a decision is due (on the map with the navigator's latest obstacles
// marked, so that it plans as the navigator will), and publishes UTILITY_SCORES,
// EXPLORE_GOAL and EXPLORE_STATUS as the manager says. The same node runs in
// the aslam-utility process and in-process on memq:// (docs/architecture.md §4).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "aslam/explore_control_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/nav_obstacles_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/lcm_util.h"
#include "common/types_lcm.h"
#include "navigation/costmap.h"
#include "utility/exploration_manager.h"
#include "utility/goal_selector.h"
#include "utility/utility_config.h"

namespace aslam {

class UtilityNode {
 public:
  UtilityNode(lcm::LCM& lcm, UtilityOptions options);

  // Keeps the exploration's record (counters, next goal id, blacklist) in `path`: read back
  // now when the file exists (a restart; returns true), rewritten atomically whenever it
  // changes. Throws std::runtime_error naming the file when it cannot be read.
  bool UseStateFile(const std::string& path);
  // The last failure to write the state file, if any (the node goes on).
  const std::optional<std::string>& state_file_error() const { return state_file_error_; }

  const Subscriptions& subscriptions() const { return subscriptions_; }
  int decisions() const { return manager_.decisions(); }
  int goals_reached() const { return manager_.goals_reached(); }
  int goals_failed() const { return manager_.goals_failed(); }
  // -1 when no goal is being pursued.
  int64_t current_goal_id() const { return manager_.current_goal_id(); }
  // Targets of reached and failed goals ("map"), and those forgiven once (tried again).
  const std::vector<Point2d>& blacklist_m() const { return manager_.blacklist_m(); }
  const std::vector<Point2d>& retried_m() const { return manager_.retried_m(); }
  // The latest decision and its wall-clock cost (diagnostic).
  const std::optional<GoalDecision>& last_decision() const { return last_decision_; }
  double last_compute_ms() const { return last_compute_ms_; }
  ExploreStatus status() const { return manager_.status(); }

 private:
  bool OnMap(MapMessage msg);
  bool OnPose(const pose_t& msg);
  bool OnGraph(const pose_graph_t& msg);
  bool OnFrontiers(const frontier_list_t& msg);
  bool OnNavStatus(const nav_status_t& msg);
  bool OnNavObstacles(const nav_obstacles_t& msg);
  bool OnControl(const explore_control_t& msg);
  // Publishes what the manager asked for, running the selector for a due decision.
  void Carry(const ExploreActions& actions);
  void Decide(const DecisionRequest& request);

  lcm::LCM& lcm_;
  GoalSelector selector_;
  ExplorationManager manager_;
  Subscriptions subscriptions_;
  PlanningObstacles nav_obstacles_;  // the navigator's latest
  std::optional<GoalDecision> last_decision_;
  double last_compute_ms_ = 0.0;
  std::string state_file_;
  ExplorationRecord saved_record_;
  std::optional<std::string> state_file_error_;
};

}  // namespace aslam
