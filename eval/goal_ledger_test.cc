#include "eval/goal_ledger.h"

#include <gtest/gtest.h>

namespace aslam {
namespace {

TEST(GoalFailureCategory, NumbersBecomeNAndPointsXY) {
  EXPECT_EQ(GoalFailureCategory("no progress for 20 s after 3 recoveries"),
            "no progress for N s after N recoveries");
  EXPECT_EQ(GoalFailureCategory("no path from (1.25, -3.50) to goal (4.00, 5.5) in the costmap"),
            "no path from (x; y) to goal (x; y) in the costmap");
  EXPECT_EQ(GoalFailureCategory("goal (-0.5, 2) is in an obstacle"),
            "goal (x; y) is in an obstacle");
  // Digits inside a word stay: "A2" is a name, not a number.
  EXPECT_EQ(GoalFailureCategory("A2 lidar"), "A2 lidar");
  EXPECT_EQ(GoalFailureCategory(""), "");
}

TEST(GoalLedger, NavigatorEndsAreRecordedWithTimesAndReasons) {
  GoalLedger ledger;
  ledger.OnFrontiers({4, 7});
  ledger.OnScores(7, 12.5);
  ledger.OnGoal(10.0, 0, false, {1, 2}, 7);
  ledger.OnNavStatus(11.0, 0, NavState::kActive, "");
  ledger.OnNavStatus(30.0, 0, NavState::kReached, "");
  ledger.OnNavStatus(31.0, 0, NavState::kReached, "");  // repeated: no change
  ledger.OnScores(4, 3.0);
  ledger.OnGoal(31.0, 1, false, {3, 4}, 4);
  ledger.OnNavStatus(50.0, 1, NavState::kFailed, "no progress for 20 s after 3 recoveries");
  ledger.OnGoal(51.0, 2, false, {5, 6}, 4);  // scores of another decision not heard
  ledger.OnNavStatus(52.0, 2, NavState::kUnreachable, "goal (5.00, 6.00) is in an obstacle");

  const auto& goals = ledger.goals();
  ASSERT_EQ(goals.size(), 3u);
  EXPECT_EQ(goals[0].outcome, GoalOutcome::kReached);
  EXPECT_EQ(goals[0].chosen_at_s, 10.0);
  EXPECT_EQ(goals[0].ended_at_s, 30.0);
  EXPECT_EQ(goals[0].path_length_at_choice_m, 12.5);
  EXPECT_EQ(goals[1].outcome, GoalOutcome::kFailed);
  EXPECT_EQ(goals[1].reason, "no progress for 20 s after 3 recoveries");
  EXPECT_EQ(goals[1].path_length_at_choice_m, 3.0);
  EXPECT_EQ(goals[2].outcome, GoalOutcome::kUnreachable);
  EXPECT_FALSE(goals[2].path_length_at_choice_m.has_value());

  const auto by_reason = ledger.CountFailuresByReason();
  ASSERT_EQ(by_reason.size(), 2u);
  EXPECT_EQ(by_reason[0].second, 1);
  EXPECT_EQ(by_reason[0].first, "failed: no progress for N s after N recoveries");
  EXPECT_EQ(by_reason[1].first, "unreachable: goal (x; y) is in an obstacle");
}

TEST(GoalLedger, ANewGoalEndsTheOldOneAsVanishedOrReplacedByItsFrontier) {
  GoalLedger ledger;
  ledger.OnFrontiers({1, 2});
  ledger.OnGoal(1.0, 0, false, {0, 0}, 1);
  ledger.OnGoal(2.0, 0, false, {0, 0}, 1);  // re-sent: the same goal
  ledger.OnFrontiers({2, 3});               // frontier 1 is gone
  ledger.OnGoal(3.0, 1, false, {1, 1}, 2);
  ledger.OnGoal(4.0, 2, false, {2, 2}, 3);  // frontier 2 still there
  ledger.OnFrontiers({3});
  ledger.OnGoal(5.0, 2, true, {}, -1);  // cancelled, its frontier 3 still there
  ledger.OnGoal(6.0, 3, false, {3, 3}, 3);
  ledger.OnFrontiers({});
  ledger.OnGoal(7.0, 3, true, {}, -1);                 // cancelled after its frontier went
  ledger.OnGoal(8.0, 4, false, {0, 0}, -1);            // the way home
  ledger.OnNavStatus(9.0, 3, NavState::kReached, "");  // a late report of an ended goal

  const auto& g = ledger.goals();
  ASSERT_EQ(g.size(), 5u);
  EXPECT_EQ(g[0].outcome, GoalOutcome::kFrontierVanished);
  EXPECT_EQ(g[0].ended_at_s, 3.0);
  EXPECT_EQ(g[1].outcome, GoalOutcome::kReplaced);
  EXPECT_EQ(g[2].outcome, GoalOutcome::kCancelled);
  EXPECT_EQ(g[3].outcome, GoalOutcome::kFrontierVanished);
  EXPECT_EQ(g[3].ended_at_s, 7.0);
  EXPECT_EQ(g[4].outcome, GoalOutcome::kOpen);
  EXPECT_FALSE(g[4].ended_at_s.has_value());

  int total = 0;
  for (const auto& [outcome, count] : ledger.CountByOutcome()) {
    total += count;
    if (outcome == GoalOutcome::kFrontierVanished) {
      EXPECT_EQ(count, 2);
    }
    if (outcome == GoalOutcome::kOpen) {
      EXPECT_EQ(count, 1);
    }
  }
  EXPECT_EQ(total, 5);
  EXPECT_TRUE(ledger.CountFailuresByReason().empty());
}

TEST(GoalLedger, DistanceDrivenCountsOnlyWhileAGoalIsPursued) {
  GoalLedger ledger;
  ledger.OnTruth({0, 0});
  ledger.OnTruth({1, 0});  // no goal yet
  ledger.OnGoal(1.0, 0, false, {5, 0}, 1);
  ledger.OnTruth({4, 0});
  ledger.OnTruth({4, 4});
  ledger.OnNavStatus(2.0, 0, NavState::kReached, "");
  ledger.OnTruth({0, 4});  // after it ended
  ASSERT_EQ(ledger.goals().size(), 1u);
  EXPECT_DOUBLE_EQ(ledger.goals()[0].driven_m, 7.0);
}

TEST(GoalLedger, OldAndUnknownGoalsAreIgnored) {
  GoalLedger ledger;
  ledger.OnGoal(1.0, 5, true, {}, -1);  // a cancel of a goal never heard
  EXPECT_TRUE(ledger.goals().empty());
  ledger.OnGoal(2.0, 5, false, {1, 1}, 1);
  ledger.OnGoal(3.0, 4, false, {2, 2}, 2);  // older id, late
  ledger.OnNavStatus(4.0, 4, NavState::kFailed, "late");
  ASSERT_EQ(ledger.goals().size(), 1u);
  EXPECT_EQ(ledger.goals()[0].outcome, GoalOutcome::kOpen);
}

}  // namespace
}  // namespace aslam
