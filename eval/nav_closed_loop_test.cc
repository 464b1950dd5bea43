#include "eval/nav_closed_loop.h"

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
#include "common/world_file.h"
#include "navigation/nav_lcm.h"

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

}  // namespace
}  // namespace aslam
