#include "eval/goal_ledger.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>

namespace aslam {

const char* GoalOutcomeName(GoalOutcome outcome) {
  switch (outcome) {
    case GoalOutcome::kReached: return "reached";
    case GoalOutcome::kFailed: return "failed";
    case GoalOutcome::kUnreachable: return "unreachable";
    case GoalOutcome::kFrontierVanished: return "frontier_vanished";
    case GoalOutcome::kReplaced: return "replaced";
    case GoalOutcome::kCancelled: return "cancelled";
    case GoalOutcome::kOpen: return "open";
  }
  return "?";
}

std::string GoalFailureCategory(const std::string& detail) {
  static const std::regex kPoint(R"(\(-?\d+(\.\d+)?, -?\d+(\.\d+)?\))");
  // A number standing alone: "A2" is a name and stays.
  static const std::regex kNumber(R"(-?\b\d+(\.\d+)?\b)");
  return std::regex_replace(std::regex_replace(detail, kPoint, "(x; y)"), kNumber, "N");
}

void GoalLedger::OnScores(int chosen_frontier_id, double chosen_path_length_m) {
  scores_chosen_frontier_id_ = chosen_frontier_id;
  scores_path_length_m_ = chosen_path_length_m;
}

void GoalLedger::OnFrontiers(std::vector<int> frontier_ids) {
  std::sort(frontier_ids.begin(), frontier_ids.end());
  frontier_ids_ = std::move(frontier_ids);
}

GoalRecord* GoalLedger::Pursued() {
  if (goals_.empty() || goals_.back().ended_at_s) return nullptr;
  return &goals_.back();
}

void GoalLedger::End(GoalRecord* goal, double t_s, GoalOutcome outcome, std::string reason) {
  goal->ended_at_s = t_s;
  goal->outcome = outcome;
  goal->reason = std::move(reason);
}

void GoalLedger::OnGoal(double t_s, int64_t goal_id, bool cancel, Point2d target_m,
                        int frontier_id) {
  GoalRecord* pursued = Pursued();
  if (!goals_.empty() && goal_id < goals_.back().goal_id) return;  // an old goal, late
  if (!goals_.empty() && goal_id == goals_.back().goal_id) {
    if (cancel && pursued != nullptr) {
      const bool frontier_gone =
          pursued->frontier_id >= 0 &&
          !std::binary_search(frontier_ids_.begin(), frontier_ids_.end(), pursued->frontier_id);
      End(pursued, t_s, frontier_gone ? GoalOutcome::kFrontierVanished : GoalOutcome::kCancelled,
          "");
    }
    return;  // a re-send, or a cancel of a goal already ended
  }
  if (cancel) return;  // a cancel of a goal never heard
  if (pursued != nullptr) {
    const bool frontier_gone =
        pursued->frontier_id >= 0 &&
        !std::binary_search(frontier_ids_.begin(), frontier_ids_.end(), pursued->frontier_id);
    End(pursued, t_s, frontier_gone ? GoalOutcome::kFrontierVanished : GoalOutcome::kReplaced, "");
  }
  GoalRecord goal;
  goal.goal_id = goal_id;
  goal.frontier_id = frontier_id;
  goal.target_m = target_m;
  goal.chosen_at_s = t_s;
  if (frontier_id >= 0 && frontier_id == scores_chosen_frontier_id_ && scores_path_length_m_ >= 0) {
    goal.path_length_at_choice_m = scores_path_length_m_;
  }
  scores_chosen_frontier_id_ = -1;  // each decision's scores serve its own goal only
  goals_.push_back(goal);
}

void GoalLedger::OnNavStatus(double t_s, int64_t goal_id, NavState state,
                             const std::string& detail) {
  GoalRecord* pursued = Pursued();
  if (pursued == nullptr || pursued->goal_id != goal_id) return;
  switch (state) {
    case NavState::kReached: End(pursued, t_s, GoalOutcome::kReached, ""); break;
    case NavState::kFailed: End(pursued, t_s, GoalOutcome::kFailed, detail); break;
    case NavState::kUnreachable: End(pursued, t_s, GoalOutcome::kUnreachable, detail); break;
    case NavState::kIdle:
    case NavState::kActive: break;
  }
}

void GoalLedger::OnTruth(Point2d position_m) {
  if (last_position_m_) {
    if (GoalRecord* pursued = Pursued()) {
      pursued->driven_m += std::hypot(position_m.x_m - last_position_m_->x_m,
                                      position_m.y_m - last_position_m_->y_m);
    }
  }
  last_position_m_ = position_m;
}

std::vector<std::pair<GoalOutcome, int>> GoalLedger::CountByOutcome() const {
  std::vector<std::pair<GoalOutcome, int>> counts;
  for (const GoalOutcome outcome : kAllGoalOutcomes) {
    counts.emplace_back(outcome, static_cast<int>(std::count_if(goals_.begin(), goals_.end(),
                                                                [outcome](const GoalRecord& g) {
                                                                  return g.outcome == outcome;
                                                                })));
  }
  return counts;
}

std::vector<std::pair<std::string, int>> GoalLedger::CountFailuresByReason() const {
  std::map<std::string, int> by_reason;
  for (const GoalRecord& g : goals_) {
    if (g.outcome == GoalOutcome::kFailed || g.outcome == GoalOutcome::kUnreachable) {
      ++by_reason[std::string(GoalOutcomeName(g.outcome)) + ": " + GoalFailureCategory(g.reason)];
    }
  }
  std::vector<std::pair<std::string, int>> counts(by_reason.begin(), by_reason.end());
  std::stable_sort(counts.begin(), counts.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return counts;
}

}  // namespace aslam
