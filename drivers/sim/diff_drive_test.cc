#include "drivers/sim/diff_drive.h"

#include <gtest/gtest.h>

#include <cmath>

namespace aslam {
namespace {

constexpr double kDtS = 0.01;

// Free interior [0, 10] x [0, 6] inside one-cell walls.
OccupancyGrid MakeRoom() {
  OccupancyGrid grid(202, 122, 0.05, {-0.05, -0.05}, OccupancyGrid::kFree);
  for (int col = 0; col < 202; ++col) grid.at({col, 0}) = grid.at({col, 121}) = 100;
  for (int row = 0; row < 122; ++row) grid.at({0, row}) = grid.at({201, row}) = 100;
  return grid;
}

TEST(DiffDriveTest, ArcIntegrationIsExact) {
  const Pose2d start{1.0, 2.0, 0.5};
  const Pose2d straight = DiffDriveBase::IntegrateArc(start, 0.4, 0.0, 2.0);
  EXPECT_NEAR(straight.x_m, 1.0 + 0.8 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(straight.y_m, 2.0 + 0.8 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(straight.yaw_rad, 0.5, 1e-12);

  // A quarter circle of radius v / w = 2 m to the left.
  const Pose2d quarter = DiffDriveBase::IntegrateArc({0.0, 0.0, 0.0}, 1.0, 0.5, M_PI);
  EXPECT_NEAR(quarter.x_m, 2.0, 1e-12);
  EXPECT_NEAR(quarter.y_m, 2.0, 1e-12);
  EXPECT_NEAR(quarter.yaw_rad, M_PI / 2, 1e-12);

  // Many small steps land on the same circle as one big one.
  Pose2d stepped = start;
  for (int i = 0; i < 1000; ++i) stepped = DiffDriveBase::IntegrateArc(stepped, 0.3, -0.7, 0.003);
  const Pose2d direct = DiffDriveBase::IntegrateArc(start, 0.3, -0.7, 3.0);
  EXPECT_NEAR(stepped.x_m, direct.x_m, 1e-10);
  EXPECT_NEAR(stepped.y_m, direct.y_m, 1e-10);
  EXPECT_NEAR(stepped.yaw_rad, direct.yaw_rad, 1e-10);

  // Tiny turn rates use the series without losing accuracy.
  const Pose2d nearly_straight = DiffDriveBase::IntegrateArc({0.0, 0.0, 0.0}, 1.0, 1e-8, 1.0);
  EXPECT_NEAR(nearly_straight.x_m, 1.0, 1e-15);
  EXPECT_NEAR(nearly_straight.y_m, 0.5e-8, 1e-20);
}

TEST(DiffDriveTest, AccelerationAndVelocityLimits) {
  const SimWorld world(MakeRoom());
  RobotOptions options;  // 0.5 m/s, 1.8 rad/s, 1 m/s^2, 3 rad/s^2
  DiffDriveBase base(options, {5.0, 3.0, 0.0});
  base.Step({10.0, -10.0}, kDtS, world);
  EXPECT_NEAR(base.velocity().linear_mps, 0.01, 1e-15);
  EXPECT_NEAR(base.velocity().angular_radps, -0.03, 1e-15);
  double previous_v = base.velocity().linear_mps, previous_w = base.velocity().angular_radps;
  for (int i = 0; i < 100; ++i) {
    ASSERT_FALSE(base.Step({10.0, -10.0}, kDtS, world).collided);
    const Twist2d& v = base.velocity();
    EXPECT_LE(std::abs(v.linear_mps - previous_v), 1.0 * kDtS + 1e-12);
    EXPECT_LE(std::abs(v.angular_radps - previous_w), 3.0 * kDtS + 1e-12);
    EXPECT_LE(std::abs(v.linear_mps), 0.5);
    EXPECT_LE(std::abs(v.angular_radps), 1.8);
    previous_v = v.linear_mps;
    previous_w = v.angular_radps;
  }
  EXPECT_DOUBLE_EQ(base.velocity().linear_mps, 0.5);      // reached after 0.5 s
  EXPECT_DOUBLE_EQ(base.velocity().angular_radps, -1.8);  // reached after 0.6 s
  // Braking is limited too.
  base.Step({0.0, 0.0}, kDtS, world);
  EXPECT_NEAR(base.velocity().linear_mps, 0.49, 1e-12);
  EXPECT_NEAR(base.velocity().angular_radps, -1.77, 1e-12);
  base.SetPose({5.0, 3.0, 0.0});
  EXPECT_EQ(base.velocity().linear_mps, 0.0);
}

TEST(DiffDriveTest, DrivingIntoAWallStopsAtContact) {
  const SimWorld world(MakeRoom());
  RobotOptions options;
  DiffDriveBase base(options, {8.0, 3.0, 0.0});  // the wall face is at x = 10
  int collisions = 0;
  for (int i = 0; i < 1000 && collisions == 0; ++i) {
    collisions += base.Step({0.5, 0.0}, kDtS, world).collided;
  }
  ASSERT_EQ(collisions, 1);
  EXPECT_NEAR(10.0 - base.pose().x_m, options.radius_m, 0.01);
  EXPECT_GE(10.0 - base.pose().x_m, options.radius_m);  // stopped before touching
  EXPECT_NEAR(base.pose().y_m, 3.0, 1e-12);
  EXPECT_EQ(base.velocity().linear_mps, 0.0);
  EXPECT_EQ(base.velocity().angular_radps, 0.0);
  EXPECT_FALSE(world.CircleCollides({base.pose().x_m, base.pose().y_m}, options.radius_m));

  // Pushing on keeps colliding without moving into the wall.
  EXPECT_TRUE(base.Step({0.5, 0.0}, kDtS, world).collided);
  EXPECT_GE(10.0 - base.pose().x_m, options.radius_m);

  // Turning in place at the wall never collides.
  for (int i = 0; i < 200; ++i) EXPECT_FALSE(base.Step({0.0, 1.5}, kDtS, world).collided);
  EXPECT_NE(base.pose().yaw_rad, 0.0);

  // Backing away is free.
  base.SetPose({base.pose().x_m, base.pose().y_m, 0.0});
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(base.Step({-0.3, 0.0}, kDtS, world).collided);
  EXPECT_LT(base.pose().x_m, 10.0 - options.radius_m - 0.1);
}

TEST(DiffDriveTest, LongStepsDoNotTunnelThroughThinWalls) {
  OccupancyGrid grid = MakeRoom();
  for (int row = 0; row < 122; ++row) grid.at({100, row}) = 100;  // x in [4.95, 5.0]
  const SimWorld world(grid);
  RobotOptions options;
  options.max_linear_accel_mps2 = 100.0;
  DiffDriveBase base(options, {4.0, 3.0, 0.0});
  // One 2.4 s step at 0.5 m/s ends at x = 5.2, clear on the far side of the wall.
  EXPECT_TRUE(base.Step({0.5, 0.0}, 2.4, world).collided);
  EXPECT_NEAR(base.pose().x_m, 4.95 - options.radius_m, 0.01);
}

TEST(DiffDriveTest, ArcIntoAWallStopsOnTheArc) {
  const SimWorld world(MakeRoom());
  RobotOptions options;
  DiffDriveBase base(options, {9.0, 3.0, 0.0});
  bool collided = false;
  for (int i = 0; i < 1000 && !collided; ++i)
    collided = base.Step({0.5, 0.3}, kDtS, world).collided;
  ASSERT_TRUE(collided);
  const double clearance = 10.0 - base.pose().x_m;
  EXPECT_NEAR(clearance, options.radius_m, 0.01);
  EXPECT_GT(base.pose().y_m, 3.0);  // it was turning left
}

}  // namespace
}  // namespace aslam
