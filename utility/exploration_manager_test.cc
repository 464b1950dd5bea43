#include "utility/exploration_manager.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace aslam {
namespace {

constexpr int64_t kSecond = 1'000'000;
const Point2d kNear{2.0, 1.0};
const Point2d kFar{4.0, 2.0};

FrontierList Frontiers(int64_t utime, const std::vector<int>& ids) {
  FrontierList list;
  list.utime = utime;
  for (int id : ids) {
    Frontier f;
    f.id = id;
    f.target_m = {static_cast<double>(id), 0.5};
    list.frontiers.push_back(f);
  }
  return list;
}

PoseGraph OneNodeGraph() {
  PoseGraph graph;
  graph.nodes.push_back({0, 0, {}});
  return graph;
}

// What a selector would answer: `frontier_id` at `target_m` chosen.
GoalDecision Chose(int frontier_id, Point2d target_m, int num_eligible = 1) {
  GoalDecision decision;
  FrontierScore score;
  score.frontier_id = frontier_id;
  score.target_m = target_m;
  score.chosen = true;
  decision.scores = {score};
  decision.chosen_index = 0;
  decision.num_eligible = num_eligible;
  return decision;
}

// Nothing eligible.
GoalDecision NoGoal() { return GoalDecision{}; }

NavStatus Nav(int64_t utime, int64_t goal_id, NavState state) {
  NavStatus status;
  status.utime = utime;
  status.goal_id = goal_id;
  status.state = state;
  return status;
}

ExplorationManager Manager(UtilityMethod method = UtilityMethod::kFd,
                           double done_timeout_s = 10.0) {
  return ExplorationManager(ExplorationOptions{method, done_timeout_s});
}

// Map and pose at `utime`; fd then only lacks frontiers.
void MapAndPose(ExplorationManager& m, int64_t utime) {
  m.OnMap(OccupancyGrid(2, 2, 0.1, {0.0, 0.0}), utime);
  m.OnPose(StampedPose{utime, {1.0, 1.0, 0.0}, 0.0, 0.0});
}

// Brings fd to its first goal: frontier 7 at kNear, goal id 0, at 1 s.
void FirstGoal(ExplorationManager& m) {
  MapAndPose(m, kSecond);
  const ExploreActions due = m.OnFrontiers(Frontiers(kSecond, {7, 9}));
  ASSERT_TRUE(due.decision.has_value());
  const ExploreActions goal = m.OnDecision(Chose(7, kNear));
  ASSERT_TRUE(goal.goal.has_value());
  ASSERT_EQ(m.current_goal_id(), 0);
}

TEST(ExplorationManager, InvalidOptionsThrow) {
  EXPECT_THROW(Manager(UtilityMethod::kFd, -1.0), std::invalid_argument);
  EXPECT_THROW(Manager(UtilityMethod::kFd, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
  EXPECT_NO_THROW(Manager(UtilityMethod::kFd, 0.0));
}

TEST(ExplorationManager, WaitsForEveryInputItsMethodNeeds) {
  ExplorationManager fd = Manager(UtilityMethod::kFd);
  const ExploreActions first = fd.OnMap(OccupancyGrid(2, 2, 0.1, {0.0, 0.0}), 100);
  EXPECT_FALSE(first.decision.has_value());
  ASSERT_TRUE(first.status.has_value());  // the first input gets a status at once
  EXPECT_EQ(first.status->state, ExploreState::kWaiting);
  EXPECT_EQ(first.status->detail, "waiting for SLAM_POSE, FRONTIERS");  // fd needs no graph
  EXPECT_EQ(first.status->utime, 100);

  ExplorationManager ours = Manager(UtilityMethod::kOurs);
  EXPECT_EQ(ours.status().detail, "waiting for SLAM_MAP, SLAM_POSE, POSE_GRAPH, FRONTIERS");
  MapAndPose(ours, 100);
  EXPECT_FALSE(ours.OnFrontiers(Frontiers(200, {7})).decision.has_value());
  EXPECT_FALSE(ours.OnGraph(PoseGraph{}, 300).decision.has_value());  // no nodes yet
  EXPECT_FALSE(ours.Ready());
  EXPECT_EQ(ours.status().state, ExploreState::kWaiting);
  EXPECT_EQ(ours.status().detail, "waiting for POSE_GRAPH");
  EXPECT_EQ(ours.status().method, UtilityMethod::kOurs);
}

TEST(ExplorationManager, TheInputThatCompletesTheSetStartsTheFirstDecision) {
  ExplorationManager m = Manager(UtilityMethod::kAgs);
  m.OnFrontiers(Frontiers(100, {7}));
  m.OnGraph(OneNodeGraph(), 200);
  EXPECT_FALSE(m.OnMap(OccupancyGrid(2, 2, 0.1, {0.0, 0.0}), 300).decision.has_value());
  const ExploreActions due = m.OnPose(StampedPose{250, {1.0, 1.0, 0.0}, 0.0, 0.0});
  ASSERT_TRUE(due.decision.has_value());
  EXPECT_EQ(due.decision->utime, 300);  // the latest input time, not the pose's
  EXPECT_EQ(due.decision->decision_id, 0);
  EXPECT_FALSE(due.status.has_value());  // the decision's own status follows OnDecision
  EXPECT_FALSE(due.goal.has_value());
  EXPECT_EQ(m.status().detail, "deciding");
  EXPECT_EQ(m.frontiers().size(), 1u);
  EXPECT_EQ(m.graph().nodes.size(), 1u);
  EXPECT_DOUBLE_EQ(m.pose().pose.x_m, 1.0);

  // Decided: later inputs do not decide again while nothing changes.
  m.OnDecision(Chose(7, kNear));
  EXPECT_FALSE(m.OnPose(StampedPose{400, {1.0, 1.0, 0.0}, 0.0, 0.0}).decision.has_value());
  EXPECT_FALSE(m.OnGraph(OneNodeGraph(), 500).decision.has_value());
}

TEST(ExplorationManager, ADecisionWithAGoalPublishesItAndItsStatus) {
  ExplorationManager m = Manager();
  MapAndPose(m, kSecond);
  const ExploreActions due = m.OnFrontiers(Frontiers(2 * kSecond, {7, 9}));
  ASSERT_TRUE(due.decision.has_value());
  EXPECT_EQ(due.decision->utime, 2 * kSecond);
  // A heartbeat was due too (1 s since the last status), but the decision's status replaces it.
  EXPECT_FALSE(due.status.has_value());
  const ExploreActions after = m.OnDecision(Chose(7, kNear, /*num_eligible=*/2));
  EXPECT_FALSE(after.decision.has_value());
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_EQ(after.goal->utime, 2 * kSecond);
  EXPECT_EQ(after.goal->goal_id, 0);
  EXPECT_FALSE(after.goal->cancel);
  EXPECT_EQ(after.goal->frontier_id, 7);
  EXPECT_DOUBLE_EQ(after.goal->target_m.x_m, kNear.x_m);
  EXPECT_DOUBLE_EQ(after.goal->target_m.y_m, kNear.y_m);
  ASSERT_TRUE(after.status.has_value());
  EXPECT_EQ(after.status->state, ExploreState::kExploring);
  EXPECT_EQ(after.status->detail, "goal 0 to frontier 7 at (2.00, 1.00)");
  EXPECT_EQ(after.status->current_goal_id, 0);
  EXPECT_EQ(after.status->decisions, 1);
  EXPECT_EQ(after.status->num_frontiers, 2);
  EXPECT_EQ(after.status->num_eligible, 2);
  EXPECT_EQ(m.decisions(), 1);
}

TEST(ExplorationManager, FrontiersDecideWithoutAGoalOrWhenTheGoalsFrontierVanished) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  // The goal's frontier is still there: keep going.
  EXPECT_FALSE(m.OnFrontiers(Frontiers(2 * kSecond, {9, 7, 12})).decision.has_value());
  // It is gone: decide again; a vanished target is neither reached nor failed.
  const ExploreActions due = m.OnFrontiers(Frontiers(3 * kSecond, {9, 12}));
  ASSERT_TRUE(due.decision.has_value());
  EXPECT_EQ(due.decision->decision_id, 1);
  EXPECT_FALSE(due.decision->vanished_goal_target_m.has_value());  // no keep_vanished_goal
  EXPECT_TRUE(m.blacklist_m().empty());
  EXPECT_EQ(m.goals_reached() + m.goals_failed(), 0);
  // The new goal supersedes the old one without a cancel.
  const ExploreActions after = m.OnDecision(Chose(9, kFar));
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_FALSE(after.goal->cancel);
  EXPECT_EQ(after.goal->goal_id, 1);

  // Without a goal every new frontier list is worth a decision.
  ExplorationManager idle = Manager();
  MapAndPose(idle, kSecond);
  ASSERT_TRUE(idle.OnFrontiers(Frontiers(kSecond, {})).decision.has_value());
  idle.OnDecision(NoGoal());
  EXPECT_FALSE(idle.OnPose(StampedPose{kSecond, {}, 0.0, 0.0}).decision.has_value());
  EXPECT_TRUE(idle.OnFrontiers(Frontiers(kSecond, {})).decision.has_value());
}

TEST(ExplorationManager, AKeptGoalWhoseFrontierVanishedIsCheckedOnceAndDecidedWhenItEnds) {
  ExplorationManager m(ExplorationOptions{UtilityMethod::kFd, 10.0, /*return_home=*/false,
                                          /*keep_vanished_goal=*/true});
  FirstGoal(m);
  EXPECT_FALSE(m.OnFrontiers(Frontiers(2 * kSecond, {9, 7})).decision.has_value());
  // Gone: the node is asked whether goal 0's target can still be reached.
  const ExploreActions check = m.OnFrontiers(Frontiers(3 * kSecond, {9, 12}));
  ASSERT_TRUE(check.decision.has_value());
  ASSERT_TRUE(check.decision->vanished_goal_target_m.has_value());
  EXPECT_EQ(check.decision->vanished_goal_target_m->x_m, kNear.x_m);
  EXPECT_EQ(check.decision->vanished_goal_target_m->y_m, kNear.y_m);
  // It can: the goal stays, nothing is published but the status, no decision is counted.
  const ExploreActions kept = m.OnGoalKept();
  EXPECT_FALSE(kept.goal.has_value());
  ASSERT_TRUE(kept.status.has_value());
  EXPECT_EQ(kept.status->current_goal_id, 0);
  EXPECT_EQ(m.decisions(), 1);
  // Later lists without its frontier ask nothing more.
  EXPECT_FALSE(m.OnFrontiers(Frontiers(4 * kSecond, {9, 12})).decision.has_value());
  EXPECT_FALSE(m.OnFrontiers(Frontiers(5 * kSecond, {12})).decision.has_value());
  // Reached: blacklisted and counted as any goal, then a plain decision.
  const ExploreActions due = m.OnNavStatus(Nav(6 * kSecond, 0, NavState::kReached));
  ASSERT_TRUE(due.decision.has_value());
  EXPECT_FALSE(due.decision->vanished_goal_target_m.has_value());
  EXPECT_EQ(m.goals_reached(), 1);
  ASSERT_EQ(m.blacklist_m().size(), 1u);

  // A vanished target that cannot be reached is answered with a decision: it replaces the goal.
  ExplorationManager replaced(ExplorationOptions{UtilityMethod::kFd, 10.0, false, true});
  FirstGoal(replaced);
  ASSERT_TRUE(replaced.OnFrontiers(Frontiers(3 * kSecond, {9})).decision.has_value());
  const ExploreActions after = replaced.OnDecision(Chose(9, kFar));
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_EQ(after.goal->goal_id, 1);
  EXPECT_EQ(replaced.decisions(), 2);
  EXPECT_TRUE(replaced.blacklist_m().empty());
}

TEST(ExplorationManager, APocketGoalWhoseFrontierVanishedIsReplacedAtOnce) {
  ExplorationManager m(ExplorationOptions{UtilityMethod::kFd, 10.0, /*return_home=*/false,
                                          /*keep_vanished_goal=*/true});
  MapAndPose(m, kSecond);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(kSecond, {7, 9})).decision.has_value());
  GoalDecision pocket = Chose(7, kNear);
  pocket.scores[0].pocket = true;  // chosen nearest first among pockets
  ASSERT_TRUE(m.OnDecision(pocket).goal.has_value());
  // Gone: a plain decision, as fd's, with no reachability check of the old target.
  const ExploreActions due = m.OnFrontiers(Frontiers(3 * kSecond, {9}));
  ASSERT_TRUE(due.decision.has_value());
  EXPECT_FALSE(due.decision->vanished_goal_target_m.has_value());
  const ExploreActions after = m.OnDecision(Chose(9, kFar));
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_EQ(after.goal->goal_id, 1);
  EXPECT_EQ(m.decisions(), 2);
}

TEST(ExplorationManager, NothingEligibleCancelsTheActiveGoalOnce) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(3 * kSecond, {})).decision.has_value());
  const ExploreActions after = m.OnDecision(NoGoal());
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_TRUE(after.goal->cancel);
  EXPECT_EQ(after.goal->goal_id, 0);
  EXPECT_EQ(after.goal->utime, 3 * kSecond);
  EXPECT_EQ(after.goal->frontier_id, -1);
  EXPECT_EQ(after.goal->target_m.x_m, 0.0);
  EXPECT_EQ(m.current_goal_id(), -1);
  // No goal left to cancel.
  ASSERT_TRUE(m.OnFrontiers(Frontiers(4 * kSecond, {})).decision.has_value());
  EXPECT_FALSE(m.OnDecision(NoGoal()).goal.has_value());
}

TEST(ExplorationManager, ReachedFailedAndUnreachableBlacklistCountAndDecide) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  // Driving: nothing to do.
  const ExploreActions active = m.OnNavStatus(Nav(2 * kSecond, 0, NavState::kActive));
  EXPECT_FALSE(active.decision.has_value());
  EXPECT_FALSE(active.goal.has_value());

  const ExploreActions reached = m.OnNavStatus(Nav(3 * kSecond, 0, NavState::kReached));
  ASSERT_TRUE(reached.decision.has_value());
  EXPECT_EQ(reached.decision->utime, 3 * kSecond);
  EXPECT_EQ(m.goals_reached(), 1);
  EXPECT_EQ(m.goals_failed(), 0);
  EXPECT_EQ(m.current_goal_id(), -1);
  ASSERT_EQ(m.blacklist_m().size(), 1u);
  EXPECT_DOUBLE_EQ(m.blacklist_m()[0].x_m, kNear.x_m);
  EXPECT_DOUBLE_EQ(m.blacklist_m()[0].y_m, kNear.y_m);
  m.OnDecision(Chose(9, kFar));
  EXPECT_EQ(m.current_goal_id(), 1);

  // The navigator repeats its word about the old goal: no second count.
  EXPECT_FALSE(m.OnNavStatus(Nav(3'100'000, 0, NavState::kReached)).decision.has_value());
  EXPECT_EQ(m.goals_reached(), 1);

  ASSERT_TRUE(m.OnNavStatus(Nav(4 * kSecond, 1, NavState::kFailed)).decision.has_value());
  EXPECT_EQ(m.goals_failed(), 1);
  ASSERT_EQ(m.blacklist_m().size(), 2u);
  EXPECT_DOUBLE_EQ(m.blacklist_m()[1].x_m, kFar.x_m);
  m.OnDecision(Chose(12, {3.0, 3.0}));
  EXPECT_EQ(m.current_goal_id(), 2);

  ASSERT_TRUE(m.OnNavStatus(Nav(5 * kSecond, 2, NavState::kUnreachable)).decision.has_value());
  EXPECT_EQ(m.goals_failed(), 2);
  EXPECT_EQ(m.blacklist_m().size(), 3u);
  const ExploreActions after = m.OnDecision(NoGoal());
  EXPECT_FALSE(after.goal.has_value());  // the navigator gave up already: no cancel
  ASSERT_TRUE(after.status.has_value());
  EXPECT_EQ(after.status->goals_reached, 1);
  EXPECT_EQ(after.status->goals_failed, 2);
  EXPECT_EQ(after.status->decisions, 4);
  EXPECT_EQ(after.status->num_eligible, 0);

  // Idle or a report about a goal without a decision pending: nothing.
  EXPECT_FALSE(m.OnNavStatus(Nav(5'500'000, 2, NavState::kIdle)).decision.has_value());
}

TEST(ExplorationManager, ForgivenBlacklistPointsMoveToRetriedAndStayInTheRecord) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  m.OnNavStatus(Nav(3 * kSecond, 0, NavState::kFailed));
  m.OnDecision(Chose(9, kFar));
  m.OnNavStatus(Nav(4 * kSecond, 1, NavState::kReached));
  ASSERT_EQ(m.blacklist_m().size(), 2u);
  m.ForgiveBlacklist({0});
  ASSERT_EQ(m.blacklist_m().size(), 1u);
  EXPECT_DOUBLE_EQ(m.blacklist_m()[0].x_m, kFar.x_m);
  ASSERT_EQ(m.retried_m().size(), 1u);
  EXPECT_DOUBLE_EQ(m.retried_m()[0].x_m, kNear.x_m);
  ExplorationManager restored = Manager();
  restored.Restore(m.record());
  EXPECT_TRUE(restored.record() == m.record());
  EXPECT_EQ(restored.retried_m().size(), 1u);
}

TEST(ExplorationManager, ARestoredRecordCarriesOnCountersIdsAndBlacklist) {
  ExplorationManager before = Manager();
  FirstGoal(before);
  before.OnNavStatus(Nav(3 * kSecond, 0, NavState::kReached));
  before.OnDecision(Chose(9, kFar));
  before.OnNavStatus(Nav(4 * kSecond, 1, NavState::kFailed));
  const ExplorationRecord record = before.record();
  EXPECT_EQ(record.decisions, 2);
  EXPECT_EQ(record.goals_reached, 1);
  EXPECT_EQ(record.goals_failed, 1);
  EXPECT_EQ(record.next_goal_id, 2);
  ASSERT_EQ(record.blacklist_m.size(), 2u);

  // A restarted utility: the same record, and the next goal gets the next id.
  ExplorationManager after = Manager();
  after.Restore(record);
  EXPECT_TRUE(after.record() == record);
  MapAndPose(after, 10 * kSecond);
  ASSERT_TRUE(after.OnFrontiers(Frontiers(10 * kSecond, {12})).decision.has_value());
  const ExploreActions goal = after.OnDecision(Chose(12, {3.0, 3.0}));
  ASSERT_TRUE(goal.goal.has_value());
  EXPECT_EQ(goal.goal->goal_id, 2);
  ASSERT_TRUE(goal.status.has_value());
  EXPECT_EQ(goal.status->decisions, 3);
  EXPECT_EQ(goal.status->goals_reached, 1);
  EXPECT_EQ(goal.status->goals_failed, 1);
  EXPECT_EQ(after.blacklist_m().size(), 2u);

  ExplorationRecord bad = record;
  bad.goals_failed = -1;
  EXPECT_THROW(Manager().Restore(bad), std::invalid_argument);
  bad = record;
  bad.blacklist_m.push_back({std::numeric_limits<double>::quiet_NaN(), 0.0});
  EXPECT_THROW(Manager().Restore(bad), std::invalid_argument);
}

TEST(ExplorationManager, GoalIdsContinueAfterTheNavigatorsLastId) {
  ExplorationManager m = Manager();
  m.OnNavStatus(Nav(50'000, 41, NavState::kReached));  // left over from an earlier run
  m.OnNavStatus(Nav(60'000, 3, NavState::kIdle));      // an older id does not lower it
  MapAndPose(m, 100'000);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(100'000, {7})).decision.has_value());
  const ExploreActions after = m.OnDecision(Chose(7, kNear));
  ASSERT_TRUE(after.goal.has_value());
  EXPECT_EQ(after.goal->goal_id, 42);

  // The largest id does not overflow.
  ExplorationManager edge = Manager();
  edge.OnNavStatus(Nav(0, std::numeric_limits<int64_t>::max(), NavState::kIdle));
  MapAndPose(edge, 100'000);
  ASSERT_TRUE(edge.OnFrontiers(Frontiers(100'000, {7})).decision.has_value());
  EXPECT_EQ(edge.OnDecision(Chose(7, kNear)).goal->goal_id, 0);
}

TEST(ExplorationManager, AGoalTheNavigatorMissedIsResentAfterASecond) {
  ExplorationManager m = Manager();
  m.OnNavStatus(Nav(0, 41, NavState::kReached));
  MapAndPose(m, 100'000);
  m.OnFrontiers(Frontiers(100'000, {7}));
  ASSERT_EQ(m.OnDecision(Chose(7, kNear)).goal->goal_id, 42);  // out at 0.1 s

  // Still on goal 41 only 0.9 s later: not yet.
  EXPECT_FALSE(m.OnNavStatus(Nav(1'000'000, 41, NavState::kReached)).goal.has_value());
  // 1 s later: again, stamped with the latest time before this report.
  m.OnPose(StampedPose{1'050'000, {1.0, 1.0, 0.0}, 0.0, 0.0});
  const ExploreActions resent = m.OnNavStatus(Nav(1'100'000, 41, NavState::kReached));
  ASSERT_TRUE(resent.goal.has_value());
  EXPECT_EQ(resent.goal->goal_id, 42);
  EXPECT_EQ(resent.goal->frontier_id, 7);
  EXPECT_DOUBLE_EQ(resent.goal->target_m.x_m, kNear.x_m);
  EXPECT_FALSE(resent.goal->cancel);
  EXPECT_EQ(resent.goal->utime, 1'050'000);
  EXPECT_FALSE(resent.decision.has_value());  // the same decision, not a new one
  EXPECT_EQ(m.decisions(), 1);
  // The clock restarts at the re-send (1.05 s).
  EXPECT_FALSE(m.OnNavStatus(Nav(2'000'000, 41, NavState::kIdle)).goal.has_value());
  EXPECT_TRUE(m.OnNavStatus(Nav(2'050'000, 41, NavState::kIdle)).goal.has_value());
  // The navigator on our goal, or on a newer one, is never answered with a re-send.
  EXPECT_FALSE(m.OnNavStatus(Nav(9 * kSecond, 42, NavState::kActive)).goal.has_value());
  EXPECT_FALSE(m.OnNavStatus(Nav(19 * kSecond, 43, NavState::kActive)).goal.has_value());
}

TEST(ExplorationManager, NoGoalNoResend) {
  ExplorationManager m = Manager();
  MapAndPose(m, kSecond);
  m.OnFrontiers(Frontiers(kSecond, {}));
  m.OnDecision(NoGoal());
  EXPECT_FALSE(m.OnNavStatus(Nav(5 * kSecond, -1, NavState::kIdle)).goal.has_value());
}

TEST(ExplorationManager, DoneAfterTheTimeoutWithoutAnEligibleFrontierUntilOneAppears) {
  ExplorationManager m = Manager(UtilityMethod::kFd, /*done_timeout_s=*/5.0);
  MapAndPose(m, kSecond);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(kSecond, {})).decision.has_value());
  const ExploreActions none = m.OnDecision(NoGoal());
  EXPECT_EQ(none.status->state, ExploreState::kExploring);
  EXPECT_EQ(none.status->detail, "no eligible frontier for 0.0 s");

  m.OnPose(StampedPose{5'900'000, {}, 0.0, 0.0});
  EXPECT_EQ(m.status().state, ExploreState::kExploring);
  EXPECT_EQ(m.status().detail, "no eligible frontier for 4.9 s");
  m.OnPose(StampedPose{6 * kSecond, {}, 0.0, 0.0});
  EXPECT_EQ(m.status().state, ExploreState::kDone);
  EXPECT_EQ(m.status().detail, "no eligible frontier for 5.0 s");

  // Later empty decisions keep the first time nothing was eligible.
  ASSERT_TRUE(m.OnFrontiers(Frontiers(7 * kSecond, {})).decision.has_value());
  EXPECT_EQ(m.OnDecision(NoGoal()).status->state, ExploreState::kDone);

  // Not latched: an eligible frontier revives the exploration and restarts the clock.
  ASSERT_TRUE(m.OnFrontiers(Frontiers(8 * kSecond, {3})).decision.has_value());
  EXPECT_EQ(m.OnDecision(Chose(3, kNear)).status->state, ExploreState::kExploring);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(9 * kSecond, {})).decision.has_value());
  const ExploreActions again = m.OnDecision(NoGoal());
  EXPECT_EQ(again.status->state, ExploreState::kExploring);
  EXPECT_EQ(again.status->detail, "no eligible frontier for 0.0 s");
}

TEST(ExplorationManager, AStampFarOffEndsNothingAndAClockStepIsFollowed) {
  ExplorationManager m = Manager(UtilityMethod::kFd, /*done_timeout_s=*/5.0);
  MapAndPose(m, 600 * kSecond);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(600 * kSecond, {})).decision.has_value());
  m.OnDecision(NoGoal());
  // One pose stamped 1000 s ahead: not 1000 s without a frontier, so not done.
  m.OnPose(StampedPose{1600 * kSecond, {}, 0.0, 0.0});
  EXPECT_EQ(m.status().state, ExploreState::kExploring);
  EXPECT_EQ(m.status().detail, "no eligible frontier for 0.0 s");
  m.OnPose(StampedPose{601 * kSecond, {}, 0.0, 0.0});
  EXPECT_EQ(m.status().detail, "no eligible frontier for 1.0 s");

  // The host clock steps 500 s back: after three inputs the timers run on the new clock,
  // and the heartbeat goes on.
  int statuses = 0;
  for (int64_t t = 100 * kSecond; t <= 108 * kSecond; t += kSecond / 2) {
    if (m.OnPose(StampedPose{t, {}, 0.0, 0.0}).status) ++statuses;
  }
  EXPECT_GE(statuses, 7);  // at 1 Hz over the last ~7 s
  EXPECT_EQ(m.status().state, ExploreState::kDone);
  EXPECT_EQ(m.status().detail, "no eligible frontier for 7.0 s");
}

TEST(ExplorationManager, StatusHeartbeatAtOneHertzOfMessageTime) {
  ExplorationManager m = Manager();
  std::vector<int64_t> heartbeats;
  for (int64_t t = 0; t <= 3 * kSecond; t += 250'000) {
    const ExploreActions a = m.OnPose(StampedPose{t, {}, 0.0, 0.0});
    if (a.status) heartbeats.push_back(a.status->utime);
  }
  EXPECT_EQ(heartbeats, (std::vector<int64_t>{0, kSecond, 2 * kSecond, 3 * kSecond}));
  // An input older than the latest does not move time back.
  EXPECT_FALSE(m.OnPose(StampedPose{kSecond, {}, 0.0, 0.0}).status.has_value());
  EXPECT_EQ(m.status().utime, 3 * kSecond);

  // A decision's status counts as the heartbeat: the next is due 1 s after it.
  m.OnMap(OccupancyGrid(2, 2, 0.1, {0.0, 0.0}), 3'100'000);
  ASSERT_TRUE(m.OnFrontiers(Frontiers(3'500'000, {7})).decision.has_value());
  ASSERT_TRUE(m.OnDecision(Chose(7, kNear)).status.has_value());
  EXPECT_FALSE(m.OnPose(StampedPose{4'400'000, {}, 0.0, 0.0}).status.has_value());
  EXPECT_TRUE(m.OnPose(StampedPose{4'500'000, {}, 0.0, 0.0}).status.has_value());
}

// --- EXPLORE_CONTROL: pause, resume, stop, return to the start --------------------------------

ExplorationManager ReturningHomeManager(double done_timeout_s = 10.0) {
  return ExplorationManager(ExplorationOptions{UtilityMethod::kFd, done_timeout_s, true});
}

TEST(ExplorationManager, PauseCancelsTheGoalUncountedAndStopsDecidingUntilResume) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  const ExploreActions paused = m.OnControl(ExploreCommand::kPause);
  ASSERT_TRUE(paused.goal.has_value());
  EXPECT_TRUE(paused.goal->cancel);
  EXPECT_EQ(paused.goal->goal_id, 0);
  ASSERT_TRUE(paused.status.has_value());  // the answer to the request
  EXPECT_EQ(paused.status->state, ExploreState::kPaused);
  EXPECT_EQ(m.current_goal_id(), -1);
  EXPECT_EQ(m.goals_failed(), 0);        // a pause is not a failure
  EXPECT_TRUE(m.blacklist_m().empty());  // and the target stays eligible

  // New frontiers and the navigator's report of the cancelled goal decide nothing.
  EXPECT_FALSE(m.OnFrontiers(Frontiers(2 * kSecond, {9})).decision.has_value());
  EXPECT_FALSE(m.OnNavStatus(Nav(3 * kSecond, 0, NavState::kIdle)).decision.has_value());
  // Paused for longer than the done timeout: still paused, never done.
  m.OnPose(StampedPose{30 * kSecond, {1.0, 1.0, 0.0}, 0.0, 0.0});
  EXPECT_EQ(m.status().state, ExploreState::kPaused);
  EXPECT_FALSE(m.OnControl(ExploreCommand::kPause).goal.has_value());  // twice: nothing new

  const ExploreActions resumed = m.OnControl(ExploreCommand::kResume);
  ASSERT_TRUE(resumed.decision.has_value());  // decides again at once
  EXPECT_EQ(resumed.decision->utime, 30 * kSecond);
  const ExploreActions goal = m.OnDecision(Chose(9, kFar));
  ASSERT_TRUE(goal.goal.has_value());
  EXPECT_EQ(goal.goal->goal_id, 1);  // a new id: the navigator knows 0
  EXPECT_EQ(m.status().state, ExploreState::kExploring);
}

TEST(ExplorationManager, ResumeWhileExploringChangesNothing) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  const ExploreActions a = m.OnControl(ExploreCommand::kResume);
  EXPECT_FALSE(a.goal.has_value());
  EXPECT_FALSE(a.decision.has_value());
  EXPECT_EQ(m.current_goal_id(), 0);
  EXPECT_EQ(a.status->state, ExploreState::kExploring);
}

TEST(ExplorationManager, StopCancelsAndEndsForGood) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  const ExploreActions stopped = m.OnControl(ExploreCommand::kStop);
  ASSERT_TRUE(stopped.goal.has_value());
  EXPECT_TRUE(stopped.goal->cancel);
  EXPECT_EQ(stopped.status->state, ExploreState::kStopped);
  EXPECT_EQ(stopped.status->detail, "stopped by request");
  EXPECT_FALSE(m.OnFrontiers(Frontiers(2 * kSecond, {9})).decision.has_value());
  EXPECT_FALSE(m.OnControl(ExploreCommand::kResume).decision.has_value());
  EXPECT_FALSE(m.OnControl(ExploreCommand::kPause).goal.has_value());
  EXPECT_EQ(m.status().state, ExploreState::kStopped);
}

TEST(ExplorationManager, ReturnHomeDrivesToTheFirstPoseThenStops) {
  ExplorationManager m = Manager();
  FirstGoal(m);  // the first pose was (1, 1)
  m.OnPose(StampedPose{2 * kSecond, {5.0, 3.0, 0.0}, 0.0, 0.0});
  ASSERT_TRUE(m.home_m().has_value());
  EXPECT_DOUBLE_EQ(m.home_m()->x_m, 1.0);

  const ExploreActions back = m.OnControl(ExploreCommand::kReturnHome);
  ASSERT_TRUE(back.goal.has_value());
  EXPECT_FALSE(back.goal->cancel);
  EXPECT_EQ(back.goal->goal_id, 1);  // replaces goal 0
  EXPECT_DOUBLE_EQ(back.goal->target_m.x_m, 1.0);
  EXPECT_DOUBLE_EQ(back.goal->target_m.y_m, 1.0);
  EXPECT_EQ(back.goal->frontier_id, -1);
  EXPECT_EQ(back.status->state, ExploreState::kReturning);

  // Frontiers that vanish and goal 0's late report do not turn it back into exploring.
  EXPECT_FALSE(m.OnFrontiers(Frontiers(2'200'000, {})).decision.has_value());
  // (Within 1 s of the goal home: no resend of it either.)
  EXPECT_FALSE(m.OnNavStatus(Nav(2'500'000, 0, NavState::kFailed)).goal.has_value());
  EXPECT_EQ(m.goals_failed(), 0);
  EXPECT_EQ(m.status().state, ExploreState::kReturning);

  m.OnNavStatus(Nav(40 * kSecond, 1, NavState::kReached));
  EXPECT_EQ(m.status().state, ExploreState::kStopped);  // a request ended it, not the frontiers
  EXPECT_EQ(m.status().detail, "returned to the start (1.00, 1.00)");
  EXPECT_EQ(m.goals_reached(), 0);  // the way home is no exploration goal
  EXPECT_EQ(m.current_goal_id(), -1);
}

TEST(ExplorationManager, TheWayHomeIsTriedThreeTimesThenTheExplorationEnds) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  int64_t goal_id = m.OnControl(ExploreCommand::kReturnHome).goal->goal_id;
  for (int attempt = 1; attempt < kReturnHomeAttempts; ++attempt) {
    NavStatus failed = Nav((10 + attempt) * kSecond, goal_id, NavState::kUnreachable);
    failed.detail = "no path";
    const ExploreActions again = m.OnNavStatus(failed);
    ASSERT_TRUE(again.goal.has_value()) << "attempt " << attempt;
    EXPECT_EQ(again.goal->goal_id, goal_id + 1);
    goal_id = again.goal->goal_id;
    EXPECT_EQ(m.status().state, ExploreState::kReturning);
  }
  NavStatus failed = Nav(20 * kSecond, goal_id, NavState::kFailed);
  failed.detail = "stuck";
  EXPECT_FALSE(m.OnNavStatus(failed).goal.has_value());
  EXPECT_EQ(m.status().state, ExploreState::kStopped);
  EXPECT_EQ(m.status().detail, "could not return to the start in 3 attempts: stuck");
}

TEST(ExplorationManager, PauseOnTheWayHomeResumesTheWayHome) {
  ExplorationManager m = Manager();
  FirstGoal(m);
  m.OnControl(ExploreCommand::kReturnHome);
  const ExploreActions paused = m.OnControl(ExploreCommand::kPause);
  ASSERT_TRUE(paused.goal.has_value());
  EXPECT_TRUE(paused.goal->cancel);
  EXPECT_EQ(m.status().detail, "paused on the way to the start");
  const ExploreActions resumed = m.OnControl(ExploreCommand::kResume);
  ASSERT_TRUE(resumed.goal.has_value());
  EXPECT_FALSE(resumed.goal->cancel);
  EXPECT_DOUBLE_EQ(resumed.goal->target_m.x_m, 1.0);
  EXPECT_FALSE(resumed.decision.has_value());
  EXPECT_EQ(m.status().state, ExploreState::kReturning);
}

TEST(ExplorationManager, ReturnHomeBeforeAnyPoseEndsAtOnce) {
  ExplorationManager m = Manager();
  const ExploreActions a = m.OnControl(ExploreCommand::kReturnHome);
  EXPECT_FALSE(a.goal.has_value());
  EXPECT_EQ(a.status->state, ExploreState::kStopped);
  EXPECT_EQ(m.status().detail, "no pose yet, so the robot is still at the start");
}

TEST(ExplorationManager, WithReturnHomeDoneDrivesToTheStartFirst) {
  ExplorationManager m = ReturningHomeManager(/*done_timeout_s=*/5.0);
  FirstGoal(m);
  m.OnPose(StampedPose{2 * kSecond, {6.0, 2.0, 0.0}, 0.0, 0.0});
  // Frontier 7 is reached and nothing else is eligible.
  ASSERT_TRUE(m.OnNavStatus(Nav(3 * kSecond, 0, NavState::kReached)).decision.has_value());
  EXPECT_FALSE(m.OnDecision(NoGoal()).goal.has_value());
  EXPECT_FALSE(m.OnPose(StampedPose{7 * kSecond, {6.0, 2.0, 0.0}, 0.0, 0.0}).goal.has_value());
  EXPECT_EQ(m.status().state, ExploreState::kExploring);  // not done before the timeout

  const ExploreActions home = m.OnPose(StampedPose{8 * kSecond, {6.0, 2.0, 0.0}, 0.0, 0.0});
  ASSERT_TRUE(home.goal.has_value());  // instead of done: the way home
  EXPECT_DOUBLE_EQ(home.goal->target_m.x_m, 1.0);
  ASSERT_TRUE(home.status.has_value());
  EXPECT_EQ(home.status->state, ExploreState::kReturning);
  m.OnNavStatus(Nav(30 * kSecond, home.goal->goal_id, NavState::kReached));
  EXPECT_EQ(m.status().state, ExploreState::kDone);  // done, at the start
  EXPECT_EQ(m.status().detail, "returned to the start (1.00, 1.00)");
}

TEST(ExplorationManager, WithReturnHomeAndNoTimeoutTheLastDecisionSendsTheRobotHome) {
  ExplorationManager m = ReturningHomeManager(/*done_timeout_s=*/0.0);
  FirstGoal(m);
  m.OnFrontiers(Frontiers(2 * kSecond, {}));  // frontier 7 vanished
  const ExploreActions a = m.OnDecision(NoGoal());
  ASSERT_TRUE(a.goal.has_value());
  EXPECT_FALSE(a.goal->cancel);  // the goal home replaces goal 0
  EXPECT_EQ(a.goal->goal_id, 1);
  EXPECT_EQ(a.status->state, ExploreState::kReturning);  // never reported done on the way
}

TEST(ExplorationManager, RequestsAndTheWayHomeSurviveARestart) {
  ExplorationManager before = Manager();
  FirstGoal(before);
  before.OnControl(ExploreCommand::kReturnHome);
  const ExplorationRecord record = before.record();
  EXPECT_EQ(record.mode, ControlMode::kReturning);

  ExplorationManager after = Manager();
  after.Restore(record);
  EXPECT_TRUE(after.record() == record);
  EXPECT_EQ(after.status().state, ExploreState::kReturning);
  // The first input after the restart sends the goal home again, with an id not yet used.
  const ExploreActions again = after.OnPose(StampedPose{50 * kSecond, {3.0, 3.0, 0.0}, 0.0, 0.0});
  ASSERT_TRUE(again.goal.has_value());
  EXPECT_GE(again.goal->goal_id, record.next_goal_id);
  EXPECT_DOUBLE_EQ(again.goal->target_m.x_m, 1.0);  // the start before the restart
  EXPECT_DOUBLE_EQ(after.home_m()->x_m, 1.0);
  after.OnMap(OccupancyGrid(2, 2, 0.1, {0.0, 0.0}), 51 * kSecond);
  EXPECT_FALSE(after.OnFrontiers(Frontiers(52 * kSecond, {7})).decision.has_value());

  ExplorationRecord paused_without_home = record;
  paused_without_home.home_m.reset();
  EXPECT_THROW(Manager().Restore(paused_without_home), std::invalid_argument);
}

TEST(ExplorationManager, CommandNamesRoundTrip) {
  for (const ExploreCommand c : {ExploreCommand::kPause, ExploreCommand::kResume,
                                 ExploreCommand::kStop, ExploreCommand::kReturnHome}) {
    EXPECT_EQ(ParseExploreCommand(ExploreCommandName(c)), c);
  }
  EXPECT_EQ(ParseExploreCommand("home"), std::nullopt);
}

}  // namespace
}  // namespace aslam
