#include "utility/utility_node.h"

#include <chrono>
#include <filesystem>
#include <utility>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/atomic_file.h"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_lcm.h"
#include "utility/exploration_record_io.h"
#include "utility/utility_lcm.h"

namespace aslam {

UtilityNode::UtilityNode(lcm::LCM& lcm, UtilityOptions options)
    : lcm_(lcm),
      selector_(SelectorOptionsForMethod(options)),
      manager_(ExplorationOptionsForMethod(options)),
      subscriptions_(lcm) {
  AddMapSubscription(subscriptions_, channels::kSlamMap,
                     [this](MapMessage m) { return OnMap(std::move(m)); });
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) { return OnPose(m); });
  subscriptions_.Add<pose_graph_t>(channels::kPoseGraph,
                                   [this](const pose_graph_t& m) { return OnGraph(m); });
  subscriptions_.Add<frontier_list_t>(channels::kFrontiers,
                                      [this](const frontier_list_t& m) { return OnFrontiers(m); });
  subscriptions_.Add<nav_status_t>(channels::kNavStatus,
                                   [this](const nav_status_t& m) { return OnNavStatus(m); });
  subscriptions_.Add<nav_obstacles_t>(
      channels::kNavObstacles, [this](const nav_obstacles_t& m) { return OnNavObstacles(m); });
  subscriptions_.Add<explore_control_t>(
      channels::kExploreControl, [this](const explore_control_t& m) { return OnControl(m); });
}

bool UtilityNode::OnMap(MapMessage msg) {
  Carry(manager_.OnMap(std::move(msg.grid), msg.utime));
  return true;
}

bool UtilityNode::OnPose(const pose_t& msg) {
  const auto pose = MapFramePoseFromLcm(msg);
  if (!pose) return false;
  Carry(manager_.OnPose(*pose));
  return true;
}

bool UtilityNode::OnGraph(const pose_graph_t& msg) {
  auto graph = FromLcm(msg);
  if (!graph) return false;
  // U1 needs a positive definite reduced Laplacian: a graph in pieces is unusable.
  if (MethodUsesGraph(selector_.options().method) && !graph->nodes.empty() &&
      !IsConnected(ToWeightedGraph(*graph))) {
    return false;
  }
  Carry(manager_.OnGraph(std::move(*graph), msg.utime));
  return true;
}

bool UtilityNode::OnFrontiers(const frontier_list_t& msg) {
  auto list = FromLcm(msg);
  if (!list) return false;
  Carry(manager_.OnFrontiers(std::move(*list)));
  return true;
}

bool UtilityNode::OnNavStatus(const nav_status_t& msg) {
  const auto status = FromLcm(msg);
  if (!status) return false;
  Carry(manager_.OnNavStatus(*status));
  return true;
}

bool UtilityNode::OnNavObstacles(const nav_obstacles_t& msg) {
  std::optional<PlanningObstacles> obstacles = FromLcm(msg);
  if (!obstacles) return false;
  nav_obstacles_ = std::move(*obstacles);
  return true;
}

bool UtilityNode::OnControl(const explore_control_t& msg) {
  const auto command = ExploreCommandFromLcm(msg.command);
  if (!command) return false;  // counted as rejected by the subscription
  Carry(manager_.OnControl(*command));
  return true;
}

bool UtilityNode::UseStateFile(const std::string& path) {
  state_file_ = path;
  const bool restart = std::filesystem::exists(path);
  if (restart) manager_.Restore(LoadExplorationRecord(path));
  saved_record_ = manager_.record();
  return restart;
}

void UtilityNode::Carry(const ExploreActions& actions) {
  if (!state_file_.empty() && !(manager_.record() == saved_record_)) {
    try {
      WriteFileAtomically(state_file_, ExplorationRecordToYaml(manager_.record()));
      saved_record_ = manager_.record();
    } catch (const std::exception& e) {
      state_file_error_ = e.what();
    }
  }
  if (actions.goal) {
    const explore_goal_t msg = ToLcm(*actions.goal);
    lcm_.publish(channels::kExploreGoal, &msg);
  }
  if (actions.decision) Decide(*actions.decision);
  if (actions.status) {
    const explore_status_t msg = ToLcm(*actions.status);
    lcm_.publish(channels::kExploreStatus, &msg);
  }
}

void UtilityNode::Decide(const DecisionRequest& request) {
  const Pose2d& robot = manager_.pose().pose;
  // Wall clock for the compute_ms diagnostic only; the decision itself uses message time.
  const auto start = std::chrono::steady_clock::now();
  // Plan as the navigator will, past the scan returns it marks; when nothing is reachable
  // that way, on the map alone (the navigator looks again before it gives such a goal up).
  const std::optional<OccupancyGrid> marked =
      WithPlanningObstacles(manager_.map(), nav_obstacles_, manager_.pose().utime);
  auto decide = [&](const OccupancyGrid& map) {
    return selector_.Decide(map, robot, manager_.graph(), manager_.frontiers(),
                            manager_.blacklist_m());
  };
  // ours' goal whose frontier vanished: it stays while its target can be reached (§9).
  if (request.vanished_goal_target_m && selector_.CanReach(marked ? *marked : manager_.map(), robot,
                                                           *request.vanished_goal_target_m)) {
    Carry(manager_.OnGoalKept());
    return;
  }
  GoalDecision decision = decide(marked ? *marked : manager_.map());
  if (!decision.has_goal() && marked) decision = decide(manager_.map());
  if (!decision.has_goal()) {
    // Reachable frontiers that only the blacklist keeps out get one more try before done.
    const std::vector<std::size_t> retry =
        selector_.PointsToRetry(decision, manager_.blacklist_m(), manager_.retried_m());
    if (!retry.empty()) {
      manager_.ForgiveBlacklist(retry);
      decision = decide(manager_.map());
    }
  }
  last_compute_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const utility_scores_t scores = ScoresToLcm(decision, request.utime, request.decision_id,
                                              selector_.options().method, robot, last_compute_ms_);
  lcm_.publish(channels::kUtilityScores, &scores);
  const ExploreActions after = manager_.OnDecision(decision);
  last_decision_ = std::move(decision);
  Carry(after);
}

}  // namespace aslam
