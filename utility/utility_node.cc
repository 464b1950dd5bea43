#include "utility/utility_node.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <string>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "common/text_format.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"

namespace aslam {
namespace {

constexpr int64_t kStatusPeriodUs = 1'000'000;
// The navigator reporting another goal this long after ours went out: it
// missed EXPLORE_GOAL (a dropped UDP message), so send it again.
constexpr int64_t kGoalResendUs = 1'000'000;

int64_t SecondsToUs(double s) { return static_cast<int64_t>(s * 1e6); }

}  // namespace

UtilityNode::UtilityNode(lcm::LCM& lcm, UtilityOptions options)
    : lcm_(lcm), options_(std::move(options)), selector_(options_.selector), subscriptions_(lcm) {
  subscriptions_.Add<occupancy_grid_t>(channels::kSlamMap,
                                       [this](const occupancy_grid_t& m) { return OnMap(m); });
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) { return OnPose(m); });
  subscriptions_.Add<pose_graph_t>(channels::kPoseGraph,
                                   [this](const pose_graph_t& m) { return OnGraph(m); });
  subscriptions_.Add<frontier_list_t>(channels::kFrontiers,
                                      [this](const frontier_list_t& m) { return OnFrontiers(m); });
  subscriptions_.Add<nav_status_t>(channels::kNavStatus,
                                   [this](const nav_status_t& m) { return OnNavStatus(m); });
}

bool UtilityNode::OnMap(const occupancy_grid_t& msg) {
  auto map = MapFrameGridFromLcm(msg);
  if (!map) return false;
  map_ = std::move(*map);
  AfterMessage(msg.utime);
  return true;
}

bool UtilityNode::OnPose(const pose_t& msg) {
  const auto pose = MapFramePoseFromLcm(msg);
  if (!pose) return false;
  pose_ = *pose;
  AfterMessage(pose->utime);
  return true;
}

bool UtilityNode::OnGraph(const pose_graph_t& msg) {
  auto graph = FromLcm(msg);
  if (!graph) return false;
  // U1 needs a positive definite reduced Laplacian: a graph in pieces is unusable.
  if (MethodUsesGraph(options_.selector.method) && !graph->nodes.empty() &&
      !IsConnected(ToWeightedGraph(*graph))) {
    return false;
  }
  graph_ = std::move(*graph);
  AfterMessage(msg.utime);
  return true;
}

bool UtilityNode::OnFrontiers(const frontier_list_t& msg) {
  auto list = FromLcm(msg);
  if (!list) return false;
  frontiers_ = std::move(*list);
  if (!goal_active_) {
    decision_pending_ = true;  // new frontiers may hold an eligible one
  } else {
    const auto& fs = frontiers_->frontiers;
    const bool still_there = std::any_of(
        fs.begin(), fs.end(), [this](const Frontier& f) { return f.id == goal_frontier_id_; });
    if (!still_there) decision_pending_ = true;
  }
  AfterMessage(msg.utime);
  return true;
}

bool UtilityNode::OnNavStatus(const nav_status_t& msg) {
  const auto report = NavReportFromLcm(msg);
  if (!report) return false;
  // Goal ids stay unique across a restart of this process: continue after the navigator's.
  if (report->goal_id < std::numeric_limits<int64_t>::max()) {
    next_goal_id_ = std::max(next_goal_id_, report->goal_id + 1);
  }
  if (goal_active_ && report->goal_id == goal_id_) {
    const bool reached = report->state == NavGoalState::kReached;
    const bool failed = report->state == NavGoalState::kFailed ||
                        report->state == NavGoalState::kUnreachable;
    if (reached || failed) {
      (reached ? goals_reached_ : goals_failed_) += 1;
      blacklist_m_.push_back(goal_target_m_);
      goal_active_ = false;
      decision_pending_ = true;
    }
  } else if (goal_active_ && report->goal_id < goal_id_ &&
             report->utime - goal_published_utime_ >= kGoalResendUs) {
    PublishGoal();
  }
  AfterMessage(report->utime);
  return true;
}

void UtilityNode::AfterMessage(int64_t utime) {
  latest_utime_ = std::max(latest_utime_, utime);
  if (decision_pending_ && Ready()) Decide();
  if (last_status_utime_ < 0 || latest_utime_ - last_status_utime_ >= kStatusPeriodUs) {
    PublishStatus();
  }
}

bool UtilityNode::Ready() const {
  const bool graph_known = graph_ && !graph_->nodes.empty();
  return map_ && pose_ && frontiers_ && (graph_known || !MethodUsesGraph(options_.selector.method));
}

std::string UtilityNode::MissingInputs() const {
  std::string missing;
  auto add = [&missing](const char* name) { missing += (missing.empty() ? "" : ", ") + std::string(name); };
  if (!map_) add("SLAM_MAP");
  if (!pose_) add("SLAM_POSE");
  if (MethodUsesGraph(options_.selector.method) && !(graph_ && !graph_->nodes.empty())) {
    add("POSE_GRAPH");
  }
  if (!frontiers_) add("FRONTIERS");
  return missing;
}

void UtilityNode::Decide() {
  decision_pending_ = false;
  static const PoseGraph kNoGraph;
  const PoseGraph& graph = graph_ ? *graph_ : kNoGraph;
  // Wall clock for the compute_ms diagnostic only; the decision itself uses message time.
  const auto start = std::chrono::steady_clock::now();
  GoalDecision decision =
      selector_.Decide(*map_, pose_->pose, graph, frontiers_->frontiers, blacklist_m_);
  last_compute_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const utility_scores_t scores = ScoresToLcm(decision, latest_utime_, decisions_,
                                              options_.selector.method, pose_->pose, last_compute_ms_);
  lcm_.publish(channels::kUtilityScores, &scores);
  ++decisions_;

  if (decision.has_goal()) {
    const FrontierScore& chosen = decision.chosen();
    goal_active_ = true;
    goal_id_ = next_goal_id_++;
    goal_frontier_id_ = chosen.frontier_id;
    goal_target_m_ = chosen.target_m;
    no_eligible_since_utime_.reset();
    PublishGoal();
  } else {
    if (goal_active_) {
      // The goal's frontier is gone and nothing replaces it: stop the navigator.
      const explore_goal_t cancel = CancelToLcm(latest_utime_, goal_id_);
      lcm_.publish(channels::kExploreGoal, &cancel);
      goal_active_ = false;
    }
    if (!no_eligible_since_utime_) no_eligible_since_utime_ = latest_utime_;
  }
  last_decision_ = std::move(decision);
  PublishStatus();
}

void UtilityNode::PublishGoal() {
  const explore_goal_t goal = GoalToLcm(latest_utime_, goal_id_, goal_target_m_, goal_frontier_id_);
  lcm_.publish(channels::kExploreGoal, &goal);
  goal_published_utime_ = latest_utime_;
}

ExploreStatus UtilityNode::status() const {
  ExploreStatus s;
  s.utime = latest_utime_;
  s.method = options_.selector.method;
  s.current_goal_id = current_goal_id();
  s.num_frontiers = frontiers_ ? static_cast<int>(frontiers_->frontiers.size()) : 0;
  s.num_eligible = last_decision_ ? last_decision_->num_eligible : 0;
  s.decisions = decisions_;
  s.goals_reached = goals_reached_;
  s.goals_failed = goals_failed_;
  if (!Ready()) {
    s.state = ExploreState::kWaiting;
    s.detail = "waiting for " + MissingInputs();
  } else if (goal_active_) {
    s.state = ExploreState::kExploring;
    s.detail = "goal " + std::to_string(goal_id_) + " to frontier " +
               std::to_string(goal_frontier_id_) +
               Format(" at (%.2f, %.2f)", goal_target_m_.x_m, goal_target_m_.y_m);
  } else if (no_eligible_since_utime_) {
    const int64_t idle_us = latest_utime_ - *no_eligible_since_utime_;
    s.state = idle_us >= SecondsToUs(options_.done_timeout_s) ? ExploreState::kDone
                                                                : ExploreState::kExploring;
    s.detail = Format("no eligible frontier for %.1f s", idle_us * 1e-6);
  } else {
    s.state = ExploreState::kExploring;
    s.detail = "deciding";
  }
  return s;
}

void UtilityNode::PublishStatus() {
  const explore_status_t msg = ToLcm(status());
  lcm_.publish(channels::kExploreStatus, &msg);
  last_status_utime_ = latest_utime_;
}

}  // namespace aslam
