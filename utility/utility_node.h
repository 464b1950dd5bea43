#pragma once

// The utility on LCM: subscribes FRONTIERS, POSE_GRAPH, SLAM_MAP, SLAM_POSE
// and NAV_STATUS; decides where to explore next (goal_selector.h) and
// publishes UTILITY_SCORES and EXPLORE_GOAL at every decision, and
// EXPLORE_STATUS at every decision and at 1 Hz of message time.
//
// A decision is made, once map, pose and frontiers (and, for ags and ours, a
// pose graph) are known, when
//   - there is no active goal and FRONTIERS arrives (or the inputs become complete),
//   - NAV_STATUS reports the active goal reached, failed or unreachable (its
//     target is blacklisted and counted),
//   - FRONTIERS no longer holds the active goal's frontier id.
// Nothing eligible: no goal (an active one is cancelled); after done_timeout_s
// of message time without an eligible frontier, EXPLORE_STATUS says done.
// The same node runs in the aslam-utility process and in-process on memq://.

#include <cstdint>
#include <optional>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "aslam/frontier_list_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/lcm_util.h"
#include "common/occupancy_grid.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "frontier/frontier.h"
#include "utility/goal_selector.h"
#include "utility/utility_config.h"
#include "utility/utility_lcm.h"

namespace aslam {

class UtilityNode {
 public:
  UtilityNode(lcm::LCM& lcm, UtilityOptions options);

  const Subscriptions& subscriptions() const { return subscriptions_; }
  int decisions() const { return decisions_; }
  int goals_reached() const { return goals_reached_; }
  int goals_failed() const { return goals_failed_; }
  // -1 when no goal is being pursued.
  int64_t current_goal_id() const { return goal_active_ ? goal_id_ : -1; }
  // Targets of reached and failed goals ("map").
  const std::vector<Point2d>& blacklist_m() const { return blacklist_m_; }
  // The latest decision and its wall-clock cost (diagnostic).
  const std::optional<GoalDecision>& last_decision() const { return last_decision_; }
  double last_compute_ms() const { return last_compute_ms_; }
  ExploreStatus status() const;

 private:
  bool OnMap(const occupancy_grid_t& msg);
  bool OnPose(const pose_t& msg);
  bool OnGraph(const pose_graph_t& msg);
  bool OnFrontiers(const frontier_list_t& msg);
  bool OnNavStatus(const nav_status_t& msg);
  // After every accepted message: a pending decision if the inputs allow, then the heartbeat.
  void AfterMessage(int64_t utime);
  bool Ready() const;
  std::string MissingInputs() const;
  void Decide();
  void PublishGoal();
  void PublishStatus();

  lcm::LCM& lcm_;
  const UtilityOptions options_;
  GoalSelector selector_;
  Subscriptions subscriptions_;

  std::optional<OccupancyGrid> map_;
  std::optional<StampedPose> pose_;
  std::optional<PoseGraph> graph_;
  std::optional<FrontierList> frontiers_;

  int64_t latest_utime_ = 0;
  int64_t last_status_utime_ = -1;
  bool decision_pending_ = true;  // no goal yet: decide as soon as the inputs allow

  bool goal_active_ = false;
  int64_t goal_id_ = -1;
  int64_t next_goal_id_ = 0;
  int goal_frontier_id_ = -1;
  Point2d goal_target_m_;
  int64_t goal_published_utime_ = 0;

  std::vector<Point2d> blacklist_m_;
  std::optional<int64_t> no_eligible_since_utime_;
  std::optional<GoalDecision> last_decision_;
  double last_compute_ms_ = 0.0;
  int decisions_ = 0;
  int goals_reached_ = 0;
  int goals_failed_ = 0;
};

}  // namespace aslam
