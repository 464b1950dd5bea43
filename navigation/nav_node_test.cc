#include "navigation/nav_node.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/types_lcm.h"
#include "navigation/nav_closed_loop.h"
#include "navigation/nav_lcm.h"
#include "worlds/worldgen.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

// worlds/test: a ring corridor 1.4 m wide, centrelines x = 0.875 / 12.225 and y = 0.875 / 9.225.
const WorldInfo& TestWorld() {
  static const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/test");
  return world;
}

struct GoalCase {
  Pose2d start;
  Point2d goal;
};

TEST(NavNodeClosedLoop, ReachesGoalsFromSeveralStartsWithoutCollision) {
  const std::vector<GoalCase> cases = {
      {{0.875, 0.875, 0.0}, {12.225, 9.225}},       // the world's start to the far corner
      {{12.225, 0.875, M_PI / 2}, {0.875, 9.225}},  // across, the other way round
      {{6.5, 9.225, M_PI}, {7.5, 0.875}},           // top to bottom, starting sideways
      {{0.875, 5.0, -M_PI / 2}, {0.875, 8.5}},      // goal straight behind the robot
  };
  for (const GoalCase& c : cases) {
    SCOPED_TRACE(::testing::Message()
                 << "start " << c.start << " goal (" << c.goal.x_m << ", " << c.goal.y_m << ")");
    const GoalRunResult result =
        RunGoal(TestWorld().map.grid, c.start, c.goal, NavOptions{}, SimulatorOptions{}, 120.0);
    EXPECT_EQ(result.state, NavState::kReached) << result.detail;
    EXPECT_EQ(result.collisions, 0);
    EXPECT_LE(result.final_distance_to_goal_m, 0.3 + 0.05);
    EXPECT_EQ(result.recoveries_used, 0);
    // No dawdling: the ring path is at most ~20 m.
    EXPECT_LT(result.time_s, 80.0);
  }
}

TEST(NavNodeClosedLoop, PublishesCommandsPerScanStatusAndPaths) {
  NavClosedLoop loop(TestWorld().map.grid, TestWorld().start, NavOptions{});
  std::vector<velocity_command_t> commands;
  std::vector<nav_status_t> statuses;
  std::vector<nav_path_t> paths;
  Subscriptions listener(loop.lcm());
  listener.Add<velocity_command_t>(channels::kCmdVel, [&](const velocity_command_t& m) {
    commands.push_back(m);
    return true;
  });
  listener.Add<nav_status_t>(channels::kNavStatus, [&](const nav_status_t& m) {
    statuses.push_back(m);
    return true;
  });
  listener.Add<nav_path_t>(channels::kNavPath, [&](const nav_path_t& m) {
    paths.push_back(m);
    return true;
  });
  loop.SendGoal(4, {6.5, 0.875});
  ASSERT_FALSE(statuses.empty());  // a goal is answered at once
  EXPECT_EQ(statuses.front().goal_id, 4);
  EXPECT_EQ(statuses.front().state, nav_status_t::STATE_ACTIVE);

  loop.RunUntil([] { return false; }, 3.0);
  EXPECT_EQ(commands.size(), 30u);  // one per scan at 10 Hz
  EXPECT_EQ(commands.back().utime, 3'000'000);
  EXPECT_GT(commands.back().linear_mps, 0.1);
  EXPECT_GE(statuses.size(), 31u);
  // A path after every replan: the first, then at 1 Hz.
  ASSERT_EQ(paths.size(), 3u);
  EXPECT_EQ(paths.front().goal_id, 4);
  EXPECT_GT(paths.front().num_points, 50);
  EXPECT_NEAR(paths.front().length_m, 5.6, 0.3);
  EXPECT_NEAR(paths.front().x_m.back(), 6.5, 0.05);
  EXPECT_GT(statuses.back().distance_remaining_m, 0.0);
  EXPECT_LT(statuses.back().distance_remaining_m, paths.front().length_m - 0.5);

  // A cancel stops the robot and idles; the path is withdrawn.
  loop.SendCancel(4);
  EXPECT_EQ(statuses.back().state, nav_status_t::STATE_IDLE);
  EXPECT_EQ(paths.back().num_points, 0);
  loop.RunUntil([] { return false; }, 2.0);
  EXPECT_EQ(commands.back().linear_mps, 0.0);
  EXPECT_EQ(commands.back().angular_radps, 0.0);
  EXPECT_LT(std::abs(loop.simulator().true_velocity().linear_mps), 1e-6);
  EXPECT_EQ(loop.simulator().collisions(), 0);
  EXPECT_EQ(loop.nav().subscriptions().total_dropped(), 0);
}

TEST(NavNodeClosedLoop, GoalInsideAWallIsUnreachable) {
  NavClosedLoop loop(TestWorld().map.grid, TestWorld().start, NavOptions{});
  loop.SendGoal(9, {0.875, 0.1});  // in the ring's outer wall
  ASSERT_TRUE(loop.RunUntilSettled(9, 5.0));
  EXPECT_EQ(loop.last_status()->state, NavState::kUnreachable);
  EXPECT_THAT(loop.last_status()->detail, HasSubstr("obstacle"));
  EXPECT_LT(loop.utime(), 200'000);  // decided on the first scan
  loop.RunUntil([] { return false; }, 1.0);
  EXPECT_LT(loop.distance_traveled_m(), 0.01);

  // Outside the building (unknown, walled off): no path.
  loop.SendGoal(10, {-0.5, 4.0});
  ASSERT_TRUE(loop.RunUntilSettled(10, 5.0));
  EXPECT_EQ(loop.last_status()->state, NavState::kUnreachable);
  EXPECT_FALSE(loop.last_status()->detail.empty());
}

// Nose 0.02 m from the corridor's south wall, facing it; the goal is behind.
const Pose2d kFacingWall{3.0, 0.175 + 0.2 + 0.02, -M_PI / 2};
const Point2d kGoalBehind{1.5, 1.2};

TEST(NavNodeClosedLoop, RecoversFromAStartFacingAWall) {
  const GoalRunResult result = RunGoal(TestWorld().map.grid, kFacingWall, kGoalBehind, NavOptions{},
                                       SimulatorOptions{}, 60.0);
  EXPECT_EQ(result.state, NavState::kReached) << result.detail;
  EXPECT_EQ(result.collisions, 0);
}

TEST(NavNodeClosedLoop, RecoveryRotatesAndBacksOffWhenTheDwaIsBlocked) {
  // Without the DWA's escape from inside its margin, the start blocks every
  // trajectory: the navigator's own recovery has to get the robot out.
  NavOptions options;
  options.dwa.escape_inside_margin = false;
  NavClosedLoop loop(TestWorld().map.grid, kFacingWall, options);
  std::vector<int8_t> phases;
  Subscriptions listener(loop.lcm());
  listener.Add<nav_status_t>(channels::kNavStatus, [&](const nav_status_t& m) {
    if (phases.empty() || phases.back() != m.recovery) phases.push_back(m.recovery);
    return true;
  });
  loop.SendGoal(1, kGoalBehind);
  ASSERT_TRUE(loop.RunUntilSettled(1, 60.0));
  EXPECT_EQ(loop.last_status()->state, NavState::kReached) << loop.last_status()->detail;
  EXPECT_EQ(loop.simulator().collisions(), 0);
  EXPECT_GE(loop.nav().navigator().status().recoveries_used, 1);
  ASSERT_GE(phases.size(), 3u);
  EXPECT_EQ(phases[0], nav_status_t::RECOVERY_NONE);
  EXPECT_EQ(phases[1], nav_status_t::RECOVERY_ROTATE);
  EXPECT_EQ(phases[2], nav_status_t::RECOVERY_BACK_OFF);
}

TEST(NavNode, BadMessagesAreDroppedAndCounted) {
  InProcessHost host;
  NavNode node(host.lcm(), NavOptions{});
  std::vector<nav_status_t> statuses;
  Subscriptions listener(host.lcm());
  listener.Add<nav_status_t>(channels::kNavStatus, [&](const nav_status_t& m) {
    statuses.push_back(m);
    return true;
  });
  const double nan = std::numeric_limits<double>::quiet_NaN();

  const char garbage[] = "not a message";
  host.lcm().publish(channels::kExploreGoal, garbage, sizeof(garbage));
  host.lcm().publish(channels::kSlamMap, garbage, sizeof(garbage));
  explore_goal_t nan_goal = ToLcm(NavGoalRequest{0, 1, false, {nan, 1.0}});
  host.lcm().publish(channels::kExploreGoal, &nan_goal);
  explore_goal_t negative_id = ToLcm(NavGoalRequest{0, -3, false, {1.0, 1.0}});
  host.lcm().publish(channels::kExploreGoal, &negative_id);
  pose_t odom_pose = ToLcm(StampedPose{0, {1.0, 1.0, 0.0}, 0.0, 0.0}, "odom");
  host.lcm().publish(channels::kSlamPose, &odom_pose);
  pose_t nan_pose = ToLcm(StampedPose{0, {nan, 1.0, 0.0}, 0.0, 0.0}, "map");
  host.lcm().publish(channels::kSlamPose, &nan_pose);
  OccupancyGrid grid(10, 10, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  occupancy_grid_t world_map = ToLcm(grid, 0, 1, "world");
  host.lcm().publish(channels::kSlamMap, &world_map);
  occupancy_grid_t short_map = ToLcm(grid, 0, 1, "map");
  short_map.num_cells = 50;
  short_map.cells.resize(50);
  host.lcm().publish(channels::kSlamMap, &short_map);
  LidarScan scan;
  scan.range_min_m = 5.0;
  scan.range_max_m = 1.0;  // min >= max
  lidar_scan_t bad_scan = ToLcm(scan);
  host.lcm().publish(channels::kLidarScan, &bad_scan);
  host.DispatchPending();

  const Subscriptions& subs = node.subscriptions();
  EXPECT_EQ(subs.stats(channels::kExploreGoal).decode_failures, 1);
  EXPECT_EQ(subs.stats(channels::kExploreGoal).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kSlamPose).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kSlamMap).decode_failures, 1);
  EXPECT_EQ(subs.stats(channels::kSlamMap).rejected, 2);
  EXPECT_EQ(subs.stats(channels::kLidarScan).rejected, 1);
  EXPECT_EQ(subs.total_dropped(), 9);
  EXPECT_EQ(node.navigator().status().goal_id, -1);
  EXPECT_FALSE(node.navigator().has_map());
  EXPECT_TRUE(statuses.empty());
  EXPECT_EQ(node.commands_published(), 0);

  // A cancel needs no coordinates; valid messages still get through.
  explore_goal_t goal = ToLcm(NavGoalRequest{0, 2, false, {1.0, 1.0}});
  host.lcm().publish(channels::kExploreGoal, &goal);
  explore_goal_t cancel = ToLcm(NavGoalRequest{0, 2, true, {nan, nan}});
  host.lcm().publish(channels::kExploreGoal, &cancel);
  host.DispatchPending();
  EXPECT_EQ(subs.stats(channels::kExploreGoal).received, 2);
  ASSERT_EQ(statuses.size(), 2u);
  EXPECT_EQ(statuses[0].state, nav_status_t::STATE_ACTIVE);
  EXPECT_EQ(statuses[1].state, nav_status_t::STATE_IDLE);
  EXPECT_EQ(subs.total_dropped(), 9);
}

TEST(NavNode, StatusKeepsComingWithoutScansAndShutdownPublishesAStop) {
  InProcessHost host;
  NavNode node(host.lcm(), NavOptions{});
  std::vector<nav_status_t> statuses;
  std::vector<velocity_command_t> commands;
  Subscriptions listener(host.lcm());
  listener.Add<nav_status_t>(channels::kNavStatus, [&](const nav_status_t& m) {
    statuses.push_back(m);
    return true;
  });
  listener.Add<velocity_command_t>(channels::kCmdVel, [&](const velocity_command_t& m) {
    commands.push_back(m);
    return true;
  });
  // Poses at 10 Hz for 3 s and no scans: NAV_STATUS at 1 Hz, no commands.
  for (int64_t utime = 100'000; utime <= 3'000'000; utime += 100'000) {
    const pose_t pose = ToLcm(StampedPose{utime, {1.0, 1.0, 0.0}, 0.0, 0.0}, "map");
    host.lcm().publish(channels::kSlamPose, &pose);
    host.DispatchPending();
  }
  ASSERT_EQ(statuses.size(), 3u);
  EXPECT_EQ(statuses[0].utime, 1'000'000);
  EXPECT_EQ(statuses[2].utime, 3'000'000);
  EXPECT_EQ(statuses[0].goal_id, -1);
  EXPECT_EQ(statuses[0].state, nav_status_t::STATE_IDLE);
  EXPECT_TRUE(commands.empty());

  node.PublishStop();
  host.DispatchPending();
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0].utime, 3'000'000);
  EXPECT_EQ(commands[0].linear_mps, 0.0);
  EXPECT_EQ(commands[0].angular_radps, 0.0);
}

TEST(NavLcm, StatusRoundTrips) {
  NavStatus status;
  status.utime = 12;
  status.goal_id = 3;
  status.state = NavState::kFailed;
  status.recovery = RecoveryPhase::kBackOff;
  status.goal_m = {1.5, -2.0};
  status.distance_remaining_m = 4.25;
  status.detail = "why";
  const auto back = FromLcm(ToLcm(status));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->utime, 12);
  EXPECT_EQ(back->goal_id, 3);
  EXPECT_EQ(back->state, NavState::kFailed);
  EXPECT_EQ(back->recovery, RecoveryPhase::kBackOff);
  EXPECT_DOUBLE_EQ(back->goal_m.y_m, -2.0);
  EXPECT_DOUBLE_EQ(back->distance_remaining_m, 4.25);
  EXPECT_EQ(back->detail, "why");
  nav_status_t bad = ToLcm(status);
  bad.state = 9;
  EXPECT_FALSE(FromLcm(bad).has_value());
}

}  // namespace
}  // namespace aslam
