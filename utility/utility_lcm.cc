#include "utility/utility_lcm.h"

#include "common/lcm_util.h"
#include "common/types_lcm.h"

namespace aslam {

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

std::optional<std::vector<FrontierScore>> FrontierScoresFromLcm(const utility_scores_t& msg) {
  if (msg.num_scores != static_cast<int>(msg.scores.size())) return std::nullopt;
  std::vector<FrontierScore> scores;
  scores.reserve(msg.scores.size());
  for (const frontier_score_t& m : msg.scores) {
    if (m.ineligible_reason < static_cast<int8_t>(Eligibility::kEligible) ||
        m.ineligible_reason > static_cast<int8_t>(Eligibility::kPocket)) {
      return std::nullopt;
    }
    FrontierScore s;
    s.frontier_id = m.frontier_id;
    s.target_m = {m.target_x_m, m.target_y_m};
    s.path_length_m = m.path_length_m;
    s.distance_m = m.distance_m;
    s.ray_cells = m.ray_cells;
    s.path_entropy_bits = m.path_entropy_bits;
    s.mean_entropy_bits = m.mean_entropy_bits;
    s.gamma = m.gamma;
    s.rho = m.rho;
    s.u1 = m.u1;
    s.u2 = m.u2;
    s.total = m.total;
    s.eligibility = static_cast<Eligibility>(m.ineligible_reason);
    s.chosen = m.chosen;
    scores.push_back(s);
  }
  return scores;
}

explore_goal_t ToLcm(const ExploreGoal& goal) {
  explore_goal_t msg{};
  msg.utime = goal.utime;
  msg.goal_id = goal.goal_id;
  msg.cancel = goal.cancel;
  msg.x_m = goal.target_m.x_m;
  msg.y_m = goal.target_m.y_m;
  msg.frontier_id = goal.frontier_id;
  return msg;
}

int8_t ExploreStateToLcm(ExploreState state) {
  switch (state) {
    case ExploreState::kWaiting: return explore_status_t::STATE_WAITING;
    case ExploreState::kExploring: return explore_status_t::STATE_EXPLORING;
    case ExploreState::kDone: return explore_status_t::STATE_DONE;
    case ExploreState::kPaused: return explore_status_t::STATE_PAUSED;
    case ExploreState::kReturning: return explore_status_t::STATE_RETURNING;
    case ExploreState::kStopped: return explore_status_t::STATE_STOPPED;
  }
  return explore_status_t::STATE_WAITING;  // unreachable: every state is listed
}

std::optional<ExploreState> ExploreStateFromLcm(int8_t code) {
  for (const ExploreState state :
       {ExploreState::kWaiting, ExploreState::kExploring, ExploreState::kDone,
        ExploreState::kPaused, ExploreState::kReturning, ExploreState::kStopped}) {
    if (ExploreStateToLcm(state) == code) return state;
  }
  return std::nullopt;
}

int8_t ExploreCommandToLcm(ExploreCommand command) {
  switch (command) {
    case ExploreCommand::kPause: return explore_control_t::PAUSE;
    case ExploreCommand::kResume: return explore_control_t::RESUME;
    case ExploreCommand::kStop: return explore_control_t::STOP;
    case ExploreCommand::kReturnHome: return explore_control_t::RETURN_HOME;
  }
  return explore_control_t::PAUSE;  // unreachable: every command is listed
}

std::optional<ExploreCommand> ExploreCommandFromLcm(int8_t code) {
  for (const ExploreCommand command : {ExploreCommand::kPause, ExploreCommand::kResume,
                                       ExploreCommand::kStop, ExploreCommand::kReturnHome}) {
    if (ExploreCommandToLcm(command) == code) return command;
  }
  return std::nullopt;
}

std::optional<ExploreStatus> FromLcm(const explore_status_t& msg) {
  const std::optional<ExploreState> state = ExploreStateFromLcm(msg.state);
  const std::optional<UtilityMethod> method = ParseUtilityMethod(msg.method);
  if (!state || !method) return std::nullopt;
  ExploreStatus status;
  status.utime = msg.utime;
  status.state = *state;
  status.method = *method;
  status.current_goal_id = msg.current_goal_id;
  status.num_frontiers = msg.num_frontiers;
  status.num_eligible = msg.num_eligible;
  status.decisions = msg.decisions;
  status.goals_reached = msg.goals_reached;
  status.goals_failed = msg.goals_failed;
  status.detail = msg.detail;
  return status;
}

explore_control_t ExploreControlMessage(ExploreCommand command, const std::string& source) {
  explore_control_t msg{};
  msg.utime = WallClockUtime();
  msg.command = ExploreCommandToLcm(command);
  msg.source = source;
  return msg;
}

explore_status_t ToLcm(const ExploreStatus& status) {
  explore_status_t msg{};
  msg.utime = status.utime;
  msg.state = ExploreStateToLcm(status.state);
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

}  // namespace aslam
