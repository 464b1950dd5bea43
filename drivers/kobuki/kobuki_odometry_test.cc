// Kobuki odometry from encoder ticks and the gyro, with the counters' 16-bit wrap.

#include "drivers/kobuki/kobuki_odometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace aslam {
namespace {

// The specification's Kobuki: 35 mm wheels, 2578.33 ticks a turn, 230 mm apart.
constexpr double kMetresPerTick = 2.0 * M_PI * 0.035 / 2578.33;

kobuki::BasicSensorData Reading(uint16_t t_ms, uint16_t left, uint16_t right) {
  kobuki::BasicSensorData b;
  b.timestamp_ms = t_ms;
  b.left_encoder = left;
  b.right_encoder = right;
  return b;
}

kobuki::InertialSensorData Gyro(double deg, double rate_degps = 0.0) {
  return {static_cast<int16_t>(std::lround(deg * 100)),
          static_cast<int16_t>(std::lround(rate_degps * 100))};
}

TEST(KobukiOdometry, StraightAcrossTheEncoderWrap) {
  KobukiOdometry odometry(KobukiGeometry{}, /*gyro_heading=*/true);
  EXPECT_FALSE(odometry.Update(0, Reading(65530, 65500, 65500), Gyro(30)).has_value());
  // 100 ticks forward on both wheels, counted across 65535 -> 0, in 20 ms of the base's
  // clock (which wraps too).
  const auto odom = odometry.Update(20000, Reading(14, 64, 64), Gyro(30));
  ASSERT_TRUE(odom.has_value());
  EXPECT_NEAR(odom->pose.x_m, 100 * kMetresPerTick, 1e-9);
  EXPECT_NEAR(odom->pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(odom->linear_velocity_mps, 100 * kMetresPerTick / 0.020, 1e-9);
  EXPECT_EQ(odom->utime, 20000);
  // And back across the wrap: 200 ticks backward.
  const auto back = odometry.Update(40000, Reading(34, 65400, 65400), Gyro(30));
  EXPECT_NEAR(back->pose.x_m, -100 * kMetresPerTick, 1e-9);
  EXPECT_LT(back->linear_velocity_mps, 0.0);
}

TEST(KobukiOdometry, HeadingFromTheGyroAcrossItsWrap) {
  KobukiOdometry odometry(KobukiGeometry{}, true);
  odometry.Update(0, Reading(0, 0, 0), Gyro(170));
  // The wheels slip (equal ticks) but the gyro turned 20° counter-clockwise through ±180°.
  const auto odom = odometry.Update(20000, Reading(20, 0, 0), Gyro(-170, 45));
  EXPECT_NEAR(odom->pose.yaw_rad, 20 * M_PI / 180, 1e-9);
  EXPECT_NEAR(odom->angular_velocity_radps, 45 * M_PI / 180, 1e-9);
  // Driving 1000 ticks at that heading goes along it (midpoint of 20° and 20°).
  const auto ahead = odometry.Update(40000, Reading(40, 1000, 1000), Gyro(-170));
  EXPECT_NEAR(ahead->pose.x_m, 1000 * kMetresPerTick * std::cos(20 * M_PI / 180), 1e-9);
  EXPECT_NEAR(ahead->pose.y_m, 1000 * kMetresPerTick * std::sin(20 * M_PI / 180), 1e-9);
}

TEST(KobukiOdometry, HeadingFromTheEncodersWhenAskedOrWithoutAGyro) {
  KobukiOdometry odometry(KobukiGeometry{}, /*gyro_heading=*/false);
  odometry.Update(0, Reading(0, 1000, 1000), Gyro(0));
  // Right forward, left backward: a turn in place of 2 * 300 ticks over the 0.23 m base.
  const auto odom = odometry.Update(50000, Reading(50, 700, 1300), Gyro(80));
  const double expected_yaw = 600 * kMetresPerTick / 0.230;
  EXPECT_NEAR(odom->pose.yaw_rad, expected_yaw, 1e-9);
  EXPECT_NEAR(odom->pose.x_m, 0.0, 1e-12);
  EXPECT_NEAR(odom->angular_velocity_radps, expected_yaw / 0.050, 1e-9);

  KobukiOdometry without_gyro(KobukiGeometry{}, true);
  without_gyro.Update(0, Reading(0, 1000, 1000), std::nullopt);
  EXPECT_NEAR(without_gyro.Update(50000, Reading(50, 700, 1300), std::nullopt)->pose.yaw_rad,
              expected_yaw, 1e-9);
}

TEST(KobukiOdometry, ARestartKeepsThePoseAndTakesNewCounters) {
  KobukiOdometry odometry(KobukiGeometry{}, true);
  odometry.Update(0, Reading(0, 0, 0), Gyro(0));
  const double x = odometry.Update(20000, Reading(20, 500, 500), Gyro(0))->pose.x_m;
  odometry.Restart();  // the base was power-cycled: counters and gyro start again elsewhere
  EXPECT_FALSE(odometry.Update(900000, Reading(7, 3, 9), Gyro(-50)).has_value());
  const auto after = odometry.Update(920000, Reading(27, 103, 109), Gyro(-50));
  EXPECT_NEAR(after->pose.x_m, x + 100 * kMetresPerTick, 1e-9);
  EXPECT_NEAR(after->pose.yaw_rad, 0.0, 1e-12);
  EXPECT_EQ(after->seq, 1);  // the sequence runs on
}

}  // namespace
}  // namespace aslam
