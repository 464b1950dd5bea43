#include "utility/utility_lcm.h"

#include <cmath>

#include "common/types_lcm.h"

namespace aslam {
namespace {

constexpr const char* kMapFrame = "map";

}  // namespace

utility_scores_t ScoresToLcm(const GoalDecision& decision, int64_t utime, int64_t decision_id,
                             UtilityMethod method, const Pose2d& robot, double compute_ms) {
  utility_scores_t msg{};
  msg.utime = utime;
  msg.decision_id = decision_id;
  msg.method = UtilityMethodName(method);
  msg.robot_pose = ToLcm(robot);
  msg.graph_nodes = decision.graph_nodes;
  msg.compute_ms = compute_ms;
  msg.chosen_frontier_id = decision.has_goal() ? decision.chosen().frontier_id : -1;
  msg.num_scores = static_cast<int32_t>(decision.scores.size());
  msg.scores.reserve(decision.scores.size());
  for (const FrontierScore& s : decision.scores) {
    frontier_score_t m{};
    m.frontier_id = s.frontier_id;
    m.target_x_m = s.target_m.x_m;
    m.target_y_m = s.target_m.y_m;
    m.path_length_m = s.path_length_m;
    m.distance_m = s.distance_m;
    m.ray_cells = s.ray_cells;
    m.path_entropy_bits = s.path_entropy_bits;
    m.mean_entropy_bits = s.mean_entropy_bits;
    m.gamma = s.gamma;
    m.rho = s.rho;
    m.u1 = s.u1;
    m.u2 = s.u2;
    m.total = s.total;
    m.eligible = s.eligible();
    m.ineligible_reason = static_cast<int8_t>(s.eligibility);
    m.chosen = s.chosen;
    msg.scores.push_back(m);
  }
  return msg;
}

explore_goal_t GoalToLcm(int64_t utime, int64_t goal_id, Point2d target_m, int frontier_id) {
  explore_goal_t msg{};
  msg.utime = utime;
  msg.goal_id = goal_id;
  msg.cancel = false;
  msg.x_m = target_m.x_m;
  msg.y_m = target_m.y_m;
  msg.frontier_id = frontier_id;
  return msg;
}

explore_goal_t CancelToLcm(int64_t utime, int64_t goal_id) {
  explore_goal_t msg{};
  msg.utime = utime;
  msg.goal_id = goal_id;
  msg.cancel = true;
  msg.x_m = 0.0;
  msg.y_m = 0.0;
  msg.frontier_id = -1;
  return msg;
}

const char* ExploreStateName(ExploreState state) {
  switch (state) {
    case ExploreState::kWaiting:
      return "waiting";
    case ExploreState::kExploring:
      return "exploring";
    case ExploreState::kDone:
      return "done";
  }
  return "?";
}

explore_status_t ToLcm(const ExploreStatus& status) {
  explore_status_t msg{};
  msg.utime = status.utime;
  switch (status.state) {
    case ExploreState::kWaiting:
      msg.state = explore_status_t::STATE_WAITING;
      break;
    case ExploreState::kExploring:
      msg.state = explore_status_t::STATE_EXPLORING;
      break;
    case ExploreState::kDone:
      msg.state = explore_status_t::STATE_DONE;
      break;
  }
  msg.method = UtilityMethodName(status.method);
  msg.current_goal_id = status.current_goal_id;
  msg.num_frontiers = status.num_frontiers;
  msg.num_eligible = status.num_eligible;
  msg.decisions = status.decisions;
  msg.goals_reached = status.goals_reached;
  msg.goals_failed = status.goals_failed;
  msg.detail = status.detail;
  return msg;
}

std::optional<NavReport> NavReportFromLcm(const nav_status_t& msg) {
  if (msg.goal_id < -1) return std::nullopt;  // -1 = no goal yet; ids are never negative
  NavReport report;
  report.utime = msg.utime;
  report.goal_id = msg.goal_id;
  switch (msg.state) {
    case nav_status_t::STATE_IDLE:
      report.state = NavGoalState::kIdle;
      break;
    case nav_status_t::STATE_ACTIVE:
      report.state = NavGoalState::kActive;
      break;
    case nav_status_t::STATE_REACHED:
      report.state = NavGoalState::kReached;
      break;
    case nav_status_t::STATE_FAILED:
      report.state = NavGoalState::kFailed;
      break;
    case nav_status_t::STATE_UNREACHABLE:
      report.state = NavGoalState::kUnreachable;
      break;
    default:
      return std::nullopt;
  }
  if (msg.recovery != nav_status_t::RECOVERY_NONE && msg.recovery != nav_status_t::RECOVERY_ROTATE &&
      msg.recovery != nav_status_t::RECOVERY_BACK_OFF) {
    return std::nullopt;
  }
  if (!std::isfinite(msg.goal_x_m) || !std::isfinite(msg.goal_y_m) ||
      !std::isfinite(msg.distance_remaining_m)) {
    return std::nullopt;
  }
  return report;
}

std::optional<StampedPose> MapFramePoseFromLcm(const pose_t& msg) {
  if (msg.frame != kMapFrame) return std::nullopt;
  return FromLcm(msg);
}

std::optional<OccupancyGrid> MapFrameGridFromLcm(const occupancy_grid_t& msg) {
  if (msg.frame != kMapFrame) return std::nullopt;
  return FromLcm(msg);
}

}  // namespace aslam
