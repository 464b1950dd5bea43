#include "common/pose2d.h"

#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

void ExpectPoseNear(const Pose2d& expected, const Pose2d& actual, double tol = 1e-12) {
  EXPECT_NEAR(expected.x_m, actual.x_m, tol);
  EXPECT_NEAR(expected.y_m, actual.y_m, tol);
  EXPECT_NEAR(0.0, WrapAngle(expected.yaw_rad - actual.yaw_rad), tol);
}

TEST(WrapAngle, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(WrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(WrapAngle(-M_PI), M_PI);  // -pi is excluded
  EXPECT_NEAR(WrapAngle(3.0 * M_PI / 2.0), -M_PI / 2.0, 1e-15);
  EXPECT_NEAR(WrapAngle(-7.0 * M_PI / 2.0), M_PI / 2.0, 1e-14);
  EXPECT_NEAR(WrapAngle(20.0 * M_PI + 0.25), 0.25, 1e-13);
}

TEST(Pose2d, ComposeMatchesHandComputedExample) {
  // Robot at (1, 2) facing +y; a point 1 m ahead and 0.5 m to its left is at (0.5, 3).
  const Pose2d robot{1.0, 2.0, M_PI / 2.0};
  const Pose2d offset{1.0, 0.5, M_PI / 2.0};
  ExpectPoseNear({0.5, 3.0, M_PI}, robot.Compose(offset));
  const Point2d p = robot.Transform({1.0, 0.5});
  EXPECT_NEAR(p.x_m, 0.5, 1e-12);
  EXPECT_NEAR(p.y_m, 3.0, 1e-12);
}

TEST(Pose2d, InverseAndBetweenAreConsistent) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-10.0, 10.0), ang(-M_PI, M_PI);
  for (int i = 0; i < 1000; ++i) {
    const Pose2d a{pos(rng), pos(rng), ang(rng)};
    const Pose2d b{pos(rng), pos(rng), ang(rng)};
    ExpectPoseNear(Pose2d{}, a.Compose(a.Inverse()), 1e-12);
    ExpectPoseNear(Pose2d{}, a.Inverse().Compose(a), 1e-12);
    ExpectPoseNear(b, a.Compose(a.Between(b)), 1e-11);
    ExpectPoseNear(a.Inverse().Compose(b), a.Between(b), 1e-11);
  }
}

TEST(Pose2d, ComposeIsAssociative) {
  const Pose2d a{1.0, -2.0, 0.3}, b{-0.5, 4.0, 2.9}, c{3.0, 1.0, -1.7};
  ExpectPoseNear((a * b) * c, a * (b * c), 1e-12);
}

TEST(Pose2d, ComposeWrapsYaw) {
  const Pose2d a{0.0, 0.0, 3.0}, b{0.0, 0.0, 3.0};
  const Pose2d c = a * b;
  EXPECT_GT(c.yaw_rad, -M_PI);
  EXPECT_LE(c.yaw_rad, M_PI);
  EXPECT_NEAR(c.yaw_rad, 6.0 - 2.0 * M_PI, 1e-12);
}

// The simulator casts from base ⊕ lidar mount: with the default (zero) mount
// that must be the base pose bit for bit, whatever the (wrapped) yaw.
TEST(Pose2d, ComposingTheIdentityKeepsAWrappedPoseBitForBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(-50.0, 50.0), ang(-M_PI, M_PI);
  std::vector<Pose2d> poses = {{0.0, 0.0, M_PI}, {1.0, -2.0, 0.0}, {3.5, 0.0, -M_PI / 2.0}};
  for (int i = 0; i < 10000; ++i) poses.push_back({pos(rng), pos(rng), WrapAngle(ang(rng))});
  for (const Pose2d& pose : poses) {
    const Pose2d composed = pose * Pose2d{};
    EXPECT_EQ(std::memcmp(&composed, &pose, sizeof(Pose2d)), 0) << pose;
  }
}

TEST(ParsePose, ParsesXYYawOnly) {
  const auto p = ParsePose("1.5,-2,0.25");
  ASSERT_TRUE(p.has_value());
  EXPECT_DOUBLE_EQ(p->x_m, 1.5);
  EXPECT_DOUBLE_EQ(p->y_m, -2.0);
  EXPECT_DOUBLE_EQ(p->yaw_rad, 0.25);
  EXPECT_TRUE(ParsePose(" 1.0 , 2.0 , 0.5 ").has_value());
  EXPECT_FALSE(ParsePose("").has_value());
  EXPECT_FALSE(ParsePose("1,2").has_value());
  EXPECT_FALSE(ParsePose("1,2,3,4").has_value());
  EXPECT_FALSE(ParsePose("1,2,3x").has_value());
  EXPECT_FALSE(ParsePose("a,b,c").has_value());
  EXPECT_FALSE(ParsePose("1;2;3").has_value());
  EXPECT_FALSE(ParsePose("1,2,1e999").has_value());
}

TEST(Pose2dTest, InterpolateGoesStraightAndTurnsTheShortWay) {
  const Pose2d a{1.0, 2.0, 3.0};
  const Pose2d b{3.0, -2.0, -3.0};  // 0.28 rad further on through ±pi, not 6 rad back
  const Pose2d half = Interpolate(a, b, 0.5);
  EXPECT_DOUBLE_EQ(half.x_m, 2.0);
  EXPECT_DOUBLE_EQ(half.y_m, 0.0);
  EXPECT_NEAR(std::abs(half.yaw_rad), M_PI, 1e-12);
  EXPECT_NEAR(Interpolate(a, b, 0.25).yaw_rad, 3.0 + 0.25 * (2 * M_PI - 6.0), 1e-12);
  EXPECT_EQ(Interpolate(a, b, 0.0).x_m, a.x_m);
  EXPECT_NEAR(Interpolate(a, b, 1.0).yaw_rad, b.yaw_rad, 1e-12);
}

}  // namespace
}  // namespace aslam
