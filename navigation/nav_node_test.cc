#include "navigation/nav_node.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "aslam/nav_obstacles_t.hpp"
#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/types_lcm.h"
#include "navigation/nav_lcm.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

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

// Publishes a parked robot's pose and a scan with every beam at `range_m` (by default walls far
// beyond the goal) at `utime` on an open map.
void PublishPoseAndScan(InProcessHost& host, int64_t utime, float range_m = 9.0f) {
  const pose_t pose = ToLcm(StampedPose{utime, {1.0, 1.0, 0.0}, 0.0, 0.0}, "map");
  host.lcm().publish(channels::kSlamPose, &pose);
  LidarScan scan;
  scan.utime = utime;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2 * M_PI / 360;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.range_m.assign(360, range_m);
  const lidar_scan_t msg = ToLcm(scan);
  host.lcm().publish(channels::kLidarScan, &msg);
  host.DispatchPending();
}

// An open 6 m map and a goal at (5, 5), so that the navigator replans.
void PublishOpenMapAndGoal(InProcessHost& host) {
  const OccupancyGrid grid(120, 120, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  const occupancy_grid_t map = ToLcm(grid, 0, 1, "map");
  host.lcm().publish(channels::kSlamMap, &map);
  const explore_goal_t goal = ToLcm(NavGoalRequest{0, 1, false, {5.0, 5.0}});
  host.lcm().publish(channels::kExploreGoal, &goal);
  host.DispatchPending();
}

TEST(NavNode, ScanClockJumpsCostOnlyTheirMessagesAndAStepIsFollowed) {
  InProcessHost host;
  NavNode node(host.lcm(), NavOptions{});
  PublishOpenMapAndGoal(host);
  constexpr int64_t kStepUs = 100'000;
  int64_t utime = 1'000'000;
  for (int i = 0; i < 20; ++i, utime += kStepUs) PublishPoseAndScan(host, utime);
  const int64_t replans_before = node.navigator().replans();
  ASSERT_GE(replans_before, 2) << node.navigator().status().detail;

  // One scan stamped 1000 s ahead is rejected; the 1 Hz replans go on.
  PublishPoseAndScan(host, utime + 1'000'000'000);
  EXPECT_EQ(node.subscriptions().stats(channels::kLidarScan).rejected, 1);
  const int64_t commands_before = node.commands_published();
  for (int i = 0; i < 30; ++i, utime += kStepUs) PublishPoseAndScan(host, utime);
  EXPECT_EQ(node.commands_published(), commands_before + 30);
  EXPECT_GE(node.navigator().replans(), replans_before + 2);

  // The host clock steps 1000 s back: after a few scans the navigator runs on the new clock.
  const int64_t replans_at_step = node.navigator().replans();
  utime -= 1'000'000'000;
  for (int i = 0; i < 40; ++i, utime += kStepUs) PublishPoseAndScan(host, utime);
  EXPECT_EQ(node.subscriptions().stats(channels::kLidarScan).rejected, 1 + 2);
  EXPECT_GE(node.navigator().replans(), replans_at_step + 2);
  EXPECT_EQ(node.navigator().status().state, NavState::kActive);
}

TEST(NavNode, PublishesTheScanReturnsItPlansAroundBeforeTheStatusOfThatCycle) {
  InProcessHost host;
  NavNode node(host.lcm(), NavOptions{});
  std::vector<std::string> order;
  std::vector<PlanningObstacles> published;
  Subscriptions listener(host.lcm());
  listener.Add<nav_obstacles_t>(channels::kNavObstacles, [&](const nav_obstacles_t& m) {
    published.push_back(*FromLcm(m));
    order.push_back("obstacles");
    return true;
  });
  listener.Add<nav_status_t>(channels::kNavStatus, [&](const nav_status_t&) {
    order.push_back("status");
    return true;
  });
  PublishOpenMapAndGoal(host);
  // Returns 1.5 m away at every beam: a ring of marks the map does not hold, taken in at the
  // next replan (1 Hz).
  PublishPoseAndScan(host, 1'000'000);  // walls at 9 m: beyond the marking range
  for (int64_t utime = 1'100'000; utime <= 2'500'000; utime += 100'000) {
    PublishPoseAndScan(host, utime, 1.5f);
  }

  ASSERT_FALSE(published.empty());
  const PlanningObstacles& obstacles = published.back();
  EXPECT_GE(obstacles.utime, 1'100'000);
  ASSERT_GT(obstacles.points_m.size(), 50u);
  for (const Point2d& p : obstacles.points_m) {
    EXPECT_NEAR(std::hypot(p.x_m - 1.0, p.y_m - 1.0), 1.5, 0.06);
  }
  // The cycle that marked them published them first, then its status.
  const auto last = std::find(order.rbegin(), order.rend(), "obstacles");
  ASSERT_NE(last, order.rend());
  ASSERT_NE(last, order.rbegin());
  EXPECT_EQ(*std::prev(last), "status");
  // The goal lies beyond the ring, which the map does not hold: the navigator looks again.
  EXPECT_EQ(node.navigator().status().state, NavState::kActive);
  EXPECT_THAT(node.navigator().status().detail, HasSubstr("scan returns"));
}

TEST(NavLcm, ObstaclesRoundTripAndMalformedOnesAreRejected) {
  const PlanningObstacles obstacles{42, {{1.025, -2.475}, {30.125, 0.025}}};
  const auto back = FromLcm(ToLcm(obstacles));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->utime, 42);
  ASSERT_EQ(back->points_m.size(), 2u);
  EXPECT_NEAR(back->points_m[0].x_m, 1.025, 1e-6);
  EXPECT_NEAR(back->points_m[1].y_m, 0.025, 1e-6);
  nav_obstacles_t short_y = ToLcm(obstacles);
  short_y.y_m.pop_back();
  EXPECT_FALSE(FromLcm(short_y).has_value());
  nav_obstacles_t nan_point = ToLcm(obstacles);
  nan_point.x_m[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(FromLcm(nan_point).has_value());
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
  nav_status_t no_goal = ToLcm(NavStatus{});
  EXPECT_EQ(FromLcm(no_goal)->goal_id, -1);  // before the first goal
  no_goal.goal_id = -2;
  EXPECT_FALSE(FromLcm(no_goal).has_value());
}

}  // namespace
}  // namespace aslam
