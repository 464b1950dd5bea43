#include "utility/utility_node.h"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/test_temp_dir.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_lcm.h"
#include "utility/explore_control_client.h"
#include "utility/utility_lcm.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kSecond = 1'000'000;

// 6 m x 4 m room at 0.1 m, free inside a one-cell border wall.
OccupancyGrid Room() {
  OccupancyGrid map(60, 40, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int c = 0; c < 60; ++c) map.at({c, 0}) = map.at({c, 39}) = OccupancyGrid::kOccupied;
  for (int r = 0; r < 40; ++r) map.at({0, r}) = map.at({59, r}) = OccupancyGrid::kOccupied;
  return map;
}

const Pose2d kRobot{1.05, 1.05, 0.0};
const Point2d kNear{2.05, 1.05};   // 1.0 m east of the robot, by line and by path
const Point2d kFar{4.05, 2.05};    // ~3.2 m
const Point2d kNorth{1.05, 3.05};  // 2.0 m

Frontier MakeFrontier(int id, Point2d target_m) {
  Frontier f;
  f.id = id;
  f.target_m = target_m;
  f.centroid_m = target_m;
  f.points_m = {target_m};
  return f;
}

// A 3-node chain ending at the robot.
PoseGraph SmallGraph() {
  PoseGraph graph;
  for (int i = 0; i < 3; ++i) {
    graph.nodes.push_back({i, i * 100'000, {0.65 + 0.2 * i, 1.05, 0.0}});
    if (i > 0) {
      PoseGraphEdge e;
      e.from_id = i - 1;
      e.to_id = i;
      e.measurement = {0.2, 0.0, 0.0};
      e.information = Eigen::Vector3d(400.0, 400.0, 1000.0).asDiagonal();
      graph.edges.push_back(e);
    }
  }
  return graph;
}

// The utility node on memq:// with a listener recording what it publishes.
class Bench {
 public:
  explicit Bench(UtilityMethod method, double done_timeout_s = 10.0)
      : node_(host_.lcm(), MakeOptions(method, done_timeout_s)), listener_(host_.lcm()) {
    listener_.Add<utility_scores_t>(channels::kUtilityScores, [this](const utility_scores_t& m) {
      scores.push_back(m);
      return true;
    });
    listener_.Add<explore_goal_t>(channels::kExploreGoal, [this](const explore_goal_t& m) {
      goals.push_back(m);
      return true;
    });
    listener_.Add<explore_status_t>(channels::kExploreStatus, [this](const explore_status_t& m) {
      statuses.push_back(m);
      return true;
    });
  }

  static UtilityOptions MakeOptions(UtilityMethod method, double done_timeout_s) {
    UtilityOptions options;
    options.selector.method = method;
    options.done_timeout_s = done_timeout_s;
    // The benches' frontiers are single cells in known space: to ours every one would be a
    // pocket, chosen nearest first (goal_selector_test.cc tests pockets).
    options.ours_pocket_max_area_m2 = 0.0;
    return options;
  }

  void Map(int64_t utime, const OccupancyGrid& map = Room()) {
    const occupancy_grid_t msg = ToLcm(map, utime, 1, "map");
    Send(channels::kSlamMap, msg);
  }
  void Pose(int64_t utime, Pose2d pose = kRobot) {
    const pose_t msg = ToLcm(StampedPose{utime, pose, 0.0, 0.0}, "map");
    Send(channels::kSlamPose, msg);
  }
  void Graph(int64_t utime, const PoseGraph& graph = SmallGraph()) {
    const pose_graph_t msg = ToLcm(graph, utime, 1, 0, 0);
    Send(channels::kPoseGraph, msg);
  }
  void Frontiers(int64_t utime, const std::vector<Frontier>& frontiers) {
    FrontierList list;
    list.utime = utime;
    list.frontiers = frontiers;
    const frontier_list_t msg = ToLcm(list);
    Send(channels::kFrontiers, msg);
  }
  void Nav(int64_t utime, int64_t goal_id, int8_t state) {
    nav_status_t msg{};
    msg.utime = utime;
    msg.goal_id = goal_id;
    msg.state = state;
    msg.recovery = nav_status_t::RECOVERY_NONE;
    msg.distance_remaining_m = -1.0;
    Send(channels::kNavStatus, msg);
  }
  template <typename Msg>
  void Send(const char* channel, const Msg& msg) {
    host_.lcm().publish(channel, &msg);
    host_.DispatchPending();
  }
  void SendBytes(const char* channel, const std::string& bytes) {
    host_.lcm().publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size()));
    host_.DispatchPending();
  }

  lcm::LCM& lcm() { return host_.lcm(); }
  const UtilityNode& node() const { return node_; }
  UtilityNode& mutable_node() { return node_; }

  std::vector<utility_scores_t> scores;
  std::vector<explore_goal_t> goals;
  std::vector<explore_status_t> statuses;

 private:
  InProcessHost host_;
  UtilityNode node_;
  Subscriptions listener_;
};

TEST(UtilityLcm, ExploreStatesRoundTripAndUnknownCodesAreRejected) {
  for (const ExploreState state :
       {ExploreState::kWaiting, ExploreState::kExploring, ExploreState::kDone,
        ExploreState::kPaused, ExploreState::kReturning, ExploreState::kStopped}) {
    EXPECT_EQ(ExploreStateFromLcm(ExploreStateToLcm(state)), state) << ExploreStateName(state);
  }
  EXPECT_EQ(ExploreStateToLcm(ExploreState::kDone), explore_status_t::STATE_DONE);
  EXPECT_EQ(ExploreStateToLcm(ExploreState::kStopped), explore_status_t::STATE_STOPPED);
  EXPECT_EQ(ExploreStateFromLcm(7), std::nullopt);
  for (const ExploreCommand command : {ExploreCommand::kPause, ExploreCommand::kResume,
                                       ExploreCommand::kStop, ExploreCommand::kReturnHome}) {
    EXPECT_EQ(ExploreCommandFromLcm(ExploreCommandToLcm(command)), command);
  }
  EXPECT_EQ(ExploreCommandToLcm(ExploreCommand::kReturnHome), explore_control_t::RETURN_HOME);
  EXPECT_EQ(ExploreCommandFromLcm(0), std::nullopt);
}

// What the viewer reads back: EXPLORE_STATUS and UTILITY_SCORES round-trip, bad ones are refused.
TEST(UtilityLcm, StatusAndScoresReadBack) {
  ExploreStatus status;
  status.utime = 42;
  status.state = ExploreState::kReturning;
  status.method = UtilityMethod::kAgs;
  status.current_goal_id = 7;
  status.num_frontiers = 5;
  status.num_eligible = 3;
  status.decisions = 9;
  status.goals_reached = 6;
  status.goals_failed = 2;
  status.detail = "returning";
  explore_status_t msg = ToLcm(status);
  const std::optional<ExploreStatus> back = FromLcm(msg);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->state, ExploreState::kReturning);
  EXPECT_EQ(back->method, UtilityMethod::kAgs);
  EXPECT_EQ(back->goals_failed, 2);
  EXPECT_EQ(back->detail, "returning");
  msg.method = "random";
  EXPECT_FALSE(FromLcm(msg).has_value());

  GoalDecision decision;
  FrontierScore score;
  score.frontier_id = 4;
  score.u1 = 1.5;
  score.ray_cells = 33;
  score.total = -std::numeric_limits<double>::infinity();
  score.eligibility = Eligibility::kUnreachable;
  decision.scores = {score};
  utility_scores_t scores = ScoresToLcm(decision, 1, 2, UtilityMethod::kOurs, Pose2d{}, 0.5);
  const auto rows = FrontierScoresFromLcm(scores);
  ASSERT_TRUE(rows.has_value());
  ASSERT_EQ(rows->size(), 1u);
  EXPECT_EQ((*rows)[0].frontier_id, 4);
  EXPECT_EQ((*rows)[0].ray_cells, 33);
  EXPECT_EQ((*rows)[0].eligibility, Eligibility::kUnreachable);
  EXPECT_DOUBLE_EQ((*rows)[0].u1, 1.5);
  scores.scores[0].ineligible_reason = 9;
  EXPECT_FALSE(FrontierScoresFromLcm(scores).has_value());
  scores.num_scores = 2;
  EXPECT_FALSE(FrontierScoresFromLcm(scores).has_value());
}

// EXPLORE_CONTROL on the bus: pause cancels the goal, resume decides again, a bad command is
// counted and dropped, and return home sends the robot to its first pose.
TEST(UtilityNode, ObeysExploreControl) {
  Bench bench(UtilityMethod::kFd);
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.goals.size(), 1u);

  auto control = [&bench](int8_t command) {
    explore_control_t msg{};
    msg.utime = 123;  // another clock: must not move the exploration's time
    msg.command = command;
    msg.source = "test";
    bench.Send(channels::kExploreControl, msg);
  };
  control(explore_control_t::PAUSE);
  ASSERT_EQ(bench.goals.size(), 2u);
  EXPECT_TRUE(bench.goals[1].cancel);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_PAUSED);
  EXPECT_EQ(bench.statuses.back().utime, 200'000);
  bench.Frontiers(1'200'000, {MakeFrontier(9, kFar)});
  EXPECT_EQ(bench.scores.size(), 1u);  // no decision while paused

  control(42);
  EXPECT_EQ(bench.node().subscriptions().stats(channels::kExploreControl).rejected, 1);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_PAUSED);

  control(explore_control_t::RESUME);
  ASSERT_EQ(bench.scores.size(), 2u);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_EXPLORING);
  ASSERT_EQ(bench.goals.size(), 3u);
  EXPECT_EQ(bench.goals[2].frontier_id, 9);

  bench.Pose(1'300'000, Pose2d{3.0, 1.0, 0.0});
  control(explore_control_t::RETURN_HOME);
  ASSERT_EQ(bench.goals.size(), 4u);
  EXPECT_EQ(bench.goals[3].frontier_id, -1);
  EXPECT_DOUBLE_EQ(bench.goals[3].x_m, kRobot.x_m);  // the first pose
  EXPECT_DOUBLE_EQ(bench.goals[3].y_m, kRobot.y_m);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_RETURNING);
  bench.Nav(9'000'000, bench.goals[3].goal_id, nav_status_t::STATE_REACHED);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_STOPPED);
  EXPECT_THAT(bench.statuses.back().detail, HasSubstr("returned to the start"));
}

TEST(UtilityNode, DecidesAndFollowsTheNavigator) {
  Bench bench(UtilityMethod::kFd);
  bench.Map(100'000);
  ASSERT_EQ(bench.statuses.size(), 1u);  // the first message gets a status at once
  EXPECT_EQ(bench.statuses[0].state, explore_status_t::STATE_WAITING);
  EXPECT_THAT(bench.statuses[0].detail, HasSubstr("SLAM_POSE"));
  EXPECT_THAT(bench.statuses[0].detail, HasSubstr("FRONTIERS"));
  EXPECT_THAT(bench.statuses[0].detail, ::testing::Not(HasSubstr("POSE_GRAPH")));  // fd needs none
  bench.Pose(100'000);
  EXPECT_TRUE(bench.scores.empty());

  bench.Frontiers(200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.scores.size(), 1u);
  const utility_scores_t& first = bench.scores[0];
  EXPECT_EQ(first.decision_id, 0);
  EXPECT_EQ(first.utime, 200'000);
  EXPECT_EQ(first.method, "fd");
  EXPECT_EQ(first.chosen_frontier_id, 7);  // the nearer by path
  EXPECT_DOUBLE_EQ(first.robot_pose.x_m, 1.05);
  EXPECT_EQ(first.graph_nodes, 0);
  EXPECT_GE(first.compute_ms, 0.0);
  ASSERT_EQ(first.num_scores, 2);
  EXPECT_EQ(first.scores[0].frontier_id, 9);
  EXPECT_FALSE(first.scores[0].chosen);
  EXPECT_TRUE(first.scores[1].chosen);
  EXPECT_TRUE(first.scores[1].eligible);
  EXPECT_NEAR(first.scores[1].path_length_m, 1.0, 1e-5);
  EXPECT_DOUBLE_EQ(first.scores[1].total, -first.scores[1].path_length_m);
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].goal_id, 0);
  EXPECT_FALSE(bench.goals[0].cancel);
  EXPECT_EQ(bench.goals[0].frontier_id, 7);
  EXPECT_DOUBLE_EQ(bench.goals[0].x_m, kNear.x_m);
  EXPECT_DOUBLE_EQ(bench.goals[0].y_m, kNear.y_m);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_EXPLORING);
  EXPECT_EQ(bench.statuses.back().current_goal_id, 0);
  EXPECT_EQ(bench.statuses.back().decisions, 1);
  EXPECT_EQ(bench.statuses.back().num_frontiers, 2);
  EXPECT_EQ(bench.statuses.back().num_eligible, 2);

  // Driving: no new decision, not even on new frontiers that still hold the goal's.
  bench.Nav(300'000, 0, nav_status_t::STATE_ACTIVE);
  bench.Frontiers(1'200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  EXPECT_EQ(bench.scores.size(), 1u);

  // Reached: a new decision at once, with the reached goal blacklisted.
  bench.Nav(5'000'000, 0, nav_status_t::STATE_REACHED);
  ASSERT_EQ(bench.scores.size(), 2u);
  const utility_scores_t& second = bench.scores[1];
  EXPECT_EQ(second.decision_id, 1);
  EXPECT_EQ(second.utime, 5'000'000);
  EXPECT_EQ(second.scores[1].frontier_id, 7);
  EXPECT_FALSE(second.scores[1].eligible);
  EXPECT_EQ(second.scores[1].ineligible_reason, frontier_score_t::INELIGIBLE_BLACKLISTED);
  EXPECT_EQ(second.scores[1].total, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(second.chosen_frontier_id, 9);
  ASSERT_EQ(bench.goals.size(), 2u);
  EXPECT_EQ(bench.goals[1].goal_id, 1);
  EXPECT_EQ(bench.goals[1].frontier_id, 9);
  EXPECT_EQ(bench.node().goals_reached(), 1);
  ASSERT_EQ(bench.node().blacklist_m().size(), 1u);
  EXPECT_DOUBLE_EQ(bench.node().blacklist_m()[0].x_m, kNear.x_m);

  // The navigator repeats its last word: no second decision for the same goal.
  bench.Nav(5'100'000, 0, nav_status_t::STATE_REACHED);
  EXPECT_EQ(bench.scores.size(), 2u);

  // Failed: blacklisted and counted. Nothing else is eligible, so the two blacklisted frontiers
  // get one more try, the nearer first (ABlacklistedReachableFrontierIsTriedOnceMoreBeforeDone).
  bench.Nav(6'000'000, 1, nav_status_t::STATE_FAILED);
  ASSERT_EQ(bench.scores.size(), 3u);
  EXPECT_EQ(bench.scores[2].chosen_frontier_id, 7);
  EXPECT_EQ(bench.node().goals_failed(), 1);
  EXPECT_TRUE(bench.node().blacklist_m().empty());
  EXPECT_EQ(bench.node().retried_m().size(), 2u);
  ASSERT_EQ(bench.goals.size(), 3u);
  EXPECT_EQ(bench.goals[2].goal_id, 2);
  const explore_status_t& status = bench.statuses.back();
  EXPECT_EQ(status.state, explore_status_t::STATE_EXPLORING);
  EXPECT_EQ(status.decisions, 3);
  EXPECT_EQ(status.goals_reached, 1);
  EXPECT_EQ(status.goals_failed, 1);
  EXPECT_EQ(status.current_goal_id, 2);

  // Unreachable counts as failed too; frontier 7 was tried twice, so only 9 is left.
  bench.Nav(7'100'000, 2, nav_status_t::STATE_UNREACHABLE);
  EXPECT_EQ(bench.node().goals_failed(), 2);
  EXPECT_EQ(bench.node().blacklist_m().size(), 1u);
  ASSERT_EQ(bench.goals.size(), 4u);
  EXPECT_EQ(bench.goals[3].frontier_id, 9);
  EXPECT_EQ(bench.node().subscriptions().total_dropped(), 0);
}

TEST(UtilityNode, PlansAroundTheNavigatorsObstacles) {
  Bench bench(UtilityMethod::kFd);
  // Scan returns the map does not hold box the nearer frontier in against the south wall.
  PlanningObstacles box{100'000, {}};
  for (int i = 0; i <= 15; ++i) {
    const double along_m = 0.05 + 0.1 * i;
    box.points_m.push_back({1.55, along_m});
    box.points_m.push_back({2.55, along_m});
    if (i <= 10) box.points_m.push_back({1.55 + 0.1 * i, 1.55});
  }
  bench.Send(channels::kNavObstacles, ToLcm(box));
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.scores.size(), 1u);
  EXPECT_EQ(bench.scores[0].chosen_frontier_id, 9);
  EXPECT_FALSE(bench.scores[0].scores[1].eligible);  // kNear: the navigator would find no path
  EXPECT_EQ(bench.node().subscriptions().total_dropped(), 0);
}

TEST(UtilityNode, WhenTheNavigatorsObstaclesShutEveryFrontierOffItPlansOnTheMapAlone) {
  // A ring of returns around the robot (clutter it came in through): no frontier is reachable
  // past it, yet exploration goes on, to the nearest frontier on the map alone.
  Bench bench(UtilityMethod::kFd, /*done_timeout_s=*/1.0);
  PlanningObstacles ring{100'000, {}};
  for (int k = 0; k < 72; ++k) {
    const double angle_rad = k * 2.0 * M_PI / 72;
    ring.points_m.push_back(
        {kRobot.x_m + 0.6 * std::cos(angle_rad), kRobot.y_m + 0.6 * std::sin(angle_rad)});
  }
  bench.Send(channels::kNavObstacles, ToLcm(ring));
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].frontier_id, 7);
  bench.Frontiers(3'000'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  EXPECT_NE(bench.statuses.back().state, explore_status_t::STATE_DONE);
}

TEST(UtilityNode, AStateFileCarriesTheCountsAcrossARestart) {
  const std::string path = TestTempPath("state.yaml");
  {
    Bench bench(UtilityMethod::kFd);
    EXPECT_FALSE(bench.mutable_node().UseStateFile(path));  // nothing to resume
    bench.Map(100'000);
    bench.Pose(100'000);
    bench.Frontiers(200'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
    bench.Nav(5'000'000, 0, nav_status_t::STATE_REACHED);
    ASSERT_EQ(bench.node().goals_reached(), 1);
    ASSERT_EQ(bench.node().decisions(), 2);
    EXPECT_FALSE(bench.node().state_file_error());
  }
  // The restarted utility: the counts go on, the reached goal stays blacklisted, ids go on.
  Bench restarted(UtilityMethod::kFd);
  EXPECT_TRUE(restarted.mutable_node().UseStateFile(path));
  EXPECT_EQ(restarted.node().goals_reached(), 1);
  EXPECT_EQ(restarted.node().decisions(), 2);
  ASSERT_EQ(restarted.node().blacklist_m().size(), 1u);
  restarted.Map(6'000'000);
  restarted.Pose(6'000'000);
  restarted.Frontiers(6'100'000, {MakeFrontier(9, kFar), MakeFrontier(7, kNear)});
  ASSERT_FALSE(restarted.scores.empty());
  EXPECT_EQ(restarted.scores.back().chosen_frontier_id, 9);  // 7 was reached before the restart
  ASSERT_FALSE(restarted.goals.empty());
  EXPECT_EQ(restarted.goals.back().goal_id, 2);
  EXPECT_EQ(restarted.statuses.back().decisions, 3);
  EXPECT_EQ(restarted.statuses.back().goals_reached, 1);
  std::filesystem::remove(path);
}

TEST(UtilityNode, DoneAfterTheTimeoutWithoutAnEligibleFrontier) {
  Bench bench(UtilityMethod::kFd, /*done_timeout_s=*/5.0);
  bench.Map(1 * kSecond);
  bench.Pose(1 * kSecond);
  bench.Frontiers(1 * kSecond, {});  // nothing to explore
  ASSERT_EQ(bench.scores.size(), 1u);
  EXPECT_EQ(bench.scores[0].num_scores, 0);
  EXPECT_TRUE(bench.goals.empty());
  // Poses at 2 Hz: EXPLORE_STATUS at 1 Hz of message time; done once 5 s have passed.
  for (int64_t t = 1'500'000; t <= 7 * kSecond; t += 500'000) bench.Pose(t);
  std::vector<int64_t> heartbeat_times;
  for (const explore_status_t& s : bench.statuses) {
    if (s.utime > 1 * kSecond) heartbeat_times.push_back(s.utime);
    if (s.decisions == 0) continue;  // before the first decision: waiting for inputs
    if (s.utime < 6 * kSecond) {
      EXPECT_EQ(s.state, explore_status_t::STATE_EXPLORING) << s.utime;
    }
    if (s.utime >= 6 * kSecond) {
      EXPECT_EQ(s.state, explore_status_t::STATE_DONE) << s.utime;
      EXPECT_THAT(s.detail, HasSubstr("no eligible frontier"));
    }
  }
  EXPECT_EQ(heartbeat_times, (std::vector<int64_t>{2 * kSecond, 3 * kSecond, 4 * kSecond,
                                                   5 * kSecond, 6 * kSecond, 7 * kSecond}));

  // A new frontier revives the exploration.
  bench.Frontiers(7'200'000, {MakeFrontier(3, kNorth)});
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].frontier_id, 3);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_EXPLORING);
}

// Issue 15: fd ended `done` with reachable frontiers left, all blacklisted by earlier goals. A
// reachable frontier that only the blacklist keeps out is tried once more; only when that goal
// ends too does the exploration end.
TEST(UtilityNode, ABlacklistedReachableFrontierIsTriedOnceMoreBeforeDone) {
  Bench bench(UtilityMethod::kFd, /*done_timeout_s=*/5.0);
  bench.Map(1 * kSecond);
  bench.Pose(1 * kSecond);
  bench.Frontiers(1 * kSecond, {MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.goals.size(), 1u);
  bench.Nav(2 * kSecond, 0, nav_status_t::STATE_FAILED);  // blacklists kNear
  ASSERT_EQ(bench.scores.size(), 2u);
  ASSERT_EQ(bench.goals.size(), 2u) << "the frontier was not tried again";
  EXPECT_EQ(bench.goals[1].goal_id, 1);
  EXPECT_EQ(bench.goals[1].frontier_id, 7);
  EXPECT_EQ(bench.scores[1].chosen_frontier_id, 7);
  EXPECT_TRUE(bench.node().blacklist_m().empty());
  ASSERT_EQ(bench.node().retried_m().size(), 1u);

  // The second try fails too: now nothing is eligible, for good, and the exploration ends.
  bench.Nav(3 * kSecond, 1, nav_status_t::STATE_FAILED);
  ASSERT_EQ(bench.scores.size(), 3u);
  EXPECT_EQ(bench.scores[2].chosen_frontier_id, -1);
  EXPECT_EQ(bench.goals.size(), 2u);
  for (int64_t t = 3'500'000; t <= 9 * kSecond; t += 500'000) bench.Pose(t);
  EXPECT_EQ(bench.statuses.back().state, explore_status_t::STATE_DONE);
  EXPECT_EQ(bench.statuses.back().goals_failed, 2);
}

TEST(UtilityNode, AVanishedFrontierTriggersADecisionAndNothingLeftCancels) {
  Bench bench(UtilityMethod::kFd);
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(100'000, {MakeFrontier(7, kNear), MakeFrontier(9, kFar)});
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].frontier_id, 7);

  bench.Frontiers(1'100'000, {MakeFrontier(9, kFar)});  // 7 was explored away
  ASSERT_EQ(bench.scores.size(), 2u);
  ASSERT_EQ(bench.goals.size(), 2u);
  EXPECT_EQ(bench.goals[1].goal_id, 1);
  EXPECT_EQ(bench.goals[1].frontier_id, 9);
  EXPECT_TRUE(bench.node().blacklist_m().empty());  // vanished is neither reached nor failed

  bench.Frontiers(2'100'000, {MakeFrontier(9, kFar), MakeFrontier(12, kNorth)});
  EXPECT_EQ(bench.scores.size(), 2u);  // 9 is still there: keep going

  bench.Frontiers(3'100'000, {});
  ASSERT_EQ(bench.scores.size(), 3u);
  ASSERT_EQ(bench.goals.size(), 3u);
  EXPECT_TRUE(bench.goals[2].cancel);
  EXPECT_EQ(bench.goals[2].goal_id, 1);
  EXPECT_EQ(bench.node().current_goal_id(), -1);
}

// ours' first goal in Room(): frontier 7 at kNear or 9 at kFar.
void OursFirstGoal(Bench& bench) {
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Graph(100'000);
  bench.Frontiers(100'000, {MakeFrontier(7, kNear), MakeFrontier(9, kFar)});
}

TEST(UtilityNode, OursDrivesOnToAVanishedGoalWhileItsTargetCanBeReached) {
  Bench bench(UtilityMethod::kOurs);
  OursFirstGoal(bench);
  ASSERT_EQ(bench.goals.size(), 1u);
  const int chosen = bench.goals[0].frontier_id;
  const Point2d target = chosen == 7 ? kNear : kFar;
  const Frontier other = chosen == 7 ? MakeFrontier(9, kFar) : MakeFrontier(7, kNear);

  bench.Frontiers(1'100'000, {other, MakeFrontier(12, kNorth)});  // the goal's frontier is gone
  EXPECT_EQ(bench.scores.size(), 1u);                             // no decision
  EXPECT_EQ(bench.goals.size(), 1u);                              // goal 0 stays
  EXPECT_EQ(bench.node().current_goal_id(), 0);
  EXPECT_EQ(bench.node().decisions(), 1);

  // Walled in (a newly seen obstacle): no longer reachable, so it is replaced at once.
  Bench walled(UtilityMethod::kOurs);
  OursFirstGoal(walled);
  ASSERT_EQ(walled.goals.size(), 1u);
  ASSERT_EQ(walled.goals[0].frontier_id, chosen);  // the same decision as above
  OccupancyGrid map = Room();
  const CellIndex t = map.WorldToCell(target);
  for (int r = t.row - 8; r <= t.row + 8; ++r) {
    for (int c = t.col - 8; c <= t.col + 8; ++c) {
      const bool ring = std::abs(r - t.row) == 8 || std::abs(c - t.col) == 8;
      if (ring && map.Contains({c, r})) map.at({c, r}) = OccupancyGrid::kOccupied;
    }
  }
  walled.Map(1'000'000, map);
  walled.Frontiers(1'100'000, {other});
  ASSERT_EQ(walled.scores.size(), 2u);
  ASSERT_EQ(walled.goals.size(), 2u);
  EXPECT_EQ(walled.goals[1].goal_id, 1);
  EXPECT_EQ(walled.goals[1].frontier_id, other.id);
  EXPECT_TRUE(walled.node().blacklist_m().empty());  // replaced, neither reached nor failed
}

TEST(UtilityNode, OursWaitsForTheGraphThenPublishesEveryTerm) {
  Bench bench(UtilityMethod::kOurs);
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(100'000, {MakeFrontier(7, kNear), MakeFrontier(9, kFar)});
  EXPECT_TRUE(bench.scores.empty());
  // (EXPLORE_STATUS goes out at 1 Hz; the node's current view says the same in between.)
  EXPECT_EQ(bench.node().status().state, ExploreState::kWaiting);
  EXPECT_EQ(bench.node().status().detail, "waiting for POSE_GRAPH");

  bench.Graph(150'000);
  ASSERT_EQ(bench.scores.size(), 1u);
  const utility_scores_t& d = bench.scores[0];
  EXPECT_EQ(d.method, "ours");
  EXPECT_EQ(d.graph_nodes, 3);
  ASSERT_EQ(d.num_scores, 2);
  for (const frontier_score_t& s : d.scores) {
    EXPECT_TRUE(s.eligible);
    EXPECT_GT(s.u1, 0.0);
    EXPECT_GT(s.u2, 0.0);
    EXPECT_GT(s.ray_cells, 1);
    EXPECT_GT(s.path_entropy_bits, 0.0);
    EXPECT_NEAR(s.mean_entropy_bits, s.path_entropy_bits / s.ray_cells, 1e-12);
    EXPECT_GT(s.gamma, 0.0);
    EXPECT_LT(s.gamma, 1.0);
    EXPECT_GE(s.rho, 10.0);
    EXPECT_DOUBLE_EQ(s.total, s.u1 + s.u2);
  }
  EXPECT_EQ(d.scores[0].chosen + d.scores[1].chosen, 1);
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].frontier_id, d.chosen_frontier_id);
  EXPECT_EQ(bench.statuses.back().method, "ours");
}

TEST(UtilityNode, GoalIdsContinueAfterTheNavigatorsAndAMissedGoalIsResent) {
  Bench bench(UtilityMethod::kFd);
  bench.Nav(50'000, 41, nav_status_t::STATE_REACHED);  // left over from an earlier run
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(100'000, {MakeFrontier(7, kNear)});
  ASSERT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(bench.goals[0].goal_id, 42);

  // The navigator still talks about goal 41: EXPLORE_GOAL was lost. Resent after 1 s.
  bench.Nav(600'000, 41, nav_status_t::STATE_REACHED);
  EXPECT_EQ(bench.goals.size(), 1u);
  bench.Nav(1'100'000, 41, nav_status_t::STATE_REACHED);
  ASSERT_EQ(bench.goals.size(), 2u);
  EXPECT_EQ(bench.goals[1].goal_id, 42);
  EXPECT_EQ(bench.goals[1].frontier_id, 7);
  EXPECT_EQ(bench.scores.size(), 1u);  // the same decision, not a new one
}

TEST(UtilityNode, BadMessagesAreDroppedAndCounted) {
  Bench bench(UtilityMethod::kOurs);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string garbage = "not a message";
  for (const char* channel : {channels::kSlamMap, channels::kSlamPose, channels::kPoseGraph,
                              channels::kFrontiers, channels::kNavStatus}) {
    bench.SendBytes(channel, garbage);
  }
  // Map: wrong frame; cells that disagree with the size.
  bench.Send(channels::kSlamMap, ToLcm(Room(), 0, 1, "world"));
  occupancy_grid_t short_map = ToLcm(Room(), 0, 1, "map");
  short_map.num_cells = 10;
  short_map.cells.resize(10);
  bench.Send(channels::kSlamMap, short_map);
  // Pose: wrong frame; not finite.
  bench.Send(channels::kSlamPose, ToLcm(StampedPose{0, kRobot, 0.0, 0.0}, "odom"));
  bench.Send(channels::kSlamPose, ToLcm(StampedPose{0, {nan, 1.0, 0.0}, 0.0, 0.0}, "map"));
  // Graph: in two pieces (no usable U1); an edge to a missing node.
  PoseGraph split = SmallGraph();
  split.edges.pop_back();
  bench.Send(channels::kPoseGraph, ToLcm(split, 0, 1, 0, 0));
  pose_graph_t dangling = ToLcm(SmallGraph(), 0, 1, 0, 0);
  dangling.edges[0].to_id = 17;
  bench.Send(channels::kPoseGraph, dangling);
  // Frontiers: a size disagreeing with its points; a non-finite target.
  FrontierList list;
  list.frontiers = {MakeFrontier(7, kNear)};
  frontier_list_t miscounted = ToLcm(list);
  miscounted.frontiers[0].size_cells = 5;
  bench.Send(channels::kFrontiers, miscounted);
  list.frontiers[0].target_m.x_m = nan;
  bench.Send(channels::kFrontiers, ToLcm(list));
  // Nav status: unknown state.
  bench.Nav(0, 0, 9);

  const Subscriptions& subs = bench.node().subscriptions();
  for (const char* channel : {channels::kSlamMap, channels::kSlamPose, channels::kPoseGraph,
                              channels::kFrontiers, channels::kNavStatus}) {
    EXPECT_EQ(subs.stats(channel).decode_failures, 1) << channel;
    EXPECT_EQ(subs.stats(channel).received, 0) << channel;
    EXPECT_EQ(subs.stats(channel).handler_errors, 0) << channel;
  }
  EXPECT_EQ(subs.stats(channels::kSlamMap).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kSlamPose).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kPoseGraph).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kFrontiers).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kNavStatus).rejected, 1);
  EXPECT_EQ(subs.total_dropped(), 14);
  EXPECT_TRUE(bench.scores.empty());
  EXPECT_TRUE(bench.goals.empty());
  EXPECT_TRUE(bench.statuses.empty());  // nothing accepted, nothing to report on

  // Good messages still get through and lead to a decision.
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Graph(100'000);
  bench.Frontiers(100'000, {MakeFrontier(7, kNear)});
  EXPECT_EQ(bench.scores.size(), 1u);
  EXPECT_EQ(bench.goals.size(), 1u);
  EXPECT_EQ(subs.total_dropped(), 14);
}

// `aslam control`: the request goes out and the utility's answer comes back.
TEST(UtilityNode, ControlClientGetsTheAnswer) {
  Bench bench(UtilityMethod::kFd);
  bench.Map(100'000);
  bench.Pose(100'000);
  bench.Frontiers(200'000, {MakeFrontier(7, kNear)});
  const auto answer = SendExploreControl(bench.lcm(), ExploreCommand::kPause, "test", 5.0);
  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(answer->state, explore_status_t::STATE_PAUSED);
  EXPECT_THAT(DescribeExploreStatus(*answer), HasSubstr("paused: paused (fd, 1 decisions"));
  EXPECT_EQ(bench.node().status().state, ExploreState::kPaused);

  InProcessHost nobody;  // no utility on this bus: no answer, after the wait
  EXPECT_FALSE(SendExploreControl(nobody.lcm(), ExploreCommand::kStop, "test", 0.1).has_value());
}

}  // namespace
}  // namespace aslam
