#pragma once

// Every goal of an exploration accounted for (a run folder's goals.csv): when it was chosen,
// how and when it ended, how far it was by the plan and how far the robot drove for it. Built
// from what the bus says (EXPLORE_GOAL, NAV_STATUS, FRONTIERS, UTILITY_SCORES) and the true
// pose, so both hostings and any recorded run account alike. On value types: times are the
// runner's simulated seconds.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/pose2d.h"
#include "navigation/navigator.h"

namespace aslam {

enum class GoalOutcome {
  kReached,
  kFailed,            // the navigator gave up after its recoveries (reason: its detail)
  kUnreachable,       // no path, or the goal in an obstacle (reason: its detail)
  kFrontierVanished,  // its frontier left FRONTIERS and the utility moved on
  kReplaced,          // a new goal while its frontier was still there
  kCancelled,         // cancelled with its frontier still there (pause, stop, return home)
  kOpen,              // still pursued when the run ended
};
inline constexpr GoalOutcome kAllGoalOutcomes[] = {
    GoalOutcome::kReached,     GoalOutcome::kFailed,
    GoalOutcome::kUnreachable, GoalOutcome::kFrontierVanished,
    GoalOutcome::kReplaced,    GoalOutcome::kCancelled,
    GoalOutcome::kOpen};
// "reached", "failed", "unreachable", "frontier_vanished", "replaced", "cancelled", "open".
const char* GoalOutcomeName(GoalOutcome outcome);

struct GoalRecord {
  int64_t goal_id = 0;
  int frontier_id = -1;  // -1: not a frontier's (the way home)
  Point2d target_m;      // "map"
  double chosen_at_s = 0.0;
  std::optional<double> ended_at_s;  // none while open
  GoalOutcome outcome = GoalOutcome::kOpen;
  std::string reason;  // the navigator's detail for failed and unreachable
  // The planned path to the target when the utility chose it (UTILITY_SCORES); none when the
  // decision's scores were not heard or the goal is not a frontier's.
  std::optional<double> path_length_at_choice_m;
  double driven_m = 0.0;  // true distance driven while the goal was pursued
};

// A navigator's detail as a category: coordinates become "(x; y)" and other numbers "N", so
// "no progress for 20 s after 3 recoveries" and "... for 20 s after 2 recoveries" count
// together ("no progress for N s after N recoveries").
std::string GoalFailureCategory(const std::string& detail);

class GoalLedger {
 public:
  // UTILITY_SCORES: the chosen frontier's planned path length (-1: none was chosen).
  void OnScores(int chosen_frontier_id, double chosen_path_length_m);
  // FRONTIERS: the ids present now.
  void OnFrontiers(std::vector<int> frontier_ids);
  // EXPLORE_GOAL. A new id ends the goal before it (replaced, or frontier vanished); a cancel
  // ends its goal; a re-sent goal changes nothing.
  void OnGoal(double t_s, int64_t goal_id, bool cancel, Point2d target_m, int frontier_id);
  // NAV_STATUS: reached, failed or unreachable ends the pursued goal of that id.
  void OnNavStatus(double t_s, int64_t goal_id, NavState state, const std::string& detail);
  // The true position, for the distance driven.
  void OnTruth(Point2d position_m);

  const std::vector<GoalRecord>& goals() const { return goals_; }
  // Goals by outcome, in kAllGoalOutcomes order.
  std::vector<std::pair<GoalOutcome, int>> CountByOutcome() const;
  // Failed and unreachable goals by GoalFailureCategory of their reason, most frequent first.
  std::vector<std::pair<std::string, int>> CountFailuresByReason() const;

 private:
  void End(GoalRecord* goal, double t_s, GoalOutcome outcome, std::string reason);
  GoalRecord* Pursued();  // the open goal, if any

  std::vector<GoalRecord> goals_;
  std::vector<int> frontier_ids_;  // sorted
  int scores_chosen_frontier_id_ = -1;
  double scores_path_length_m_ = -1.0;
  std::optional<Point2d> last_position_m_;
};

}  // namespace aslam
