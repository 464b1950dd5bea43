#include "common/types_lcm.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace aslam {
namespace {

// Encodes and decodes through LCM's wire format, as a subscriber would see it.
template <typename Msg>
Msg WireRoundTrip(const Msg& msg) {
  std::vector<uint8_t> buffer(msg.getEncodedSize());
  EXPECT_EQ(msg.encode(buffer.data(), 0, buffer.size()), static_cast<int>(buffer.size()));
  Msg decoded{};
  EXPECT_EQ(decoded.decode(buffer.data(), 0, buffer.size()), static_cast<int>(buffer.size()));
  return decoded;
}

TEST(TypesLcm, LidarScanRoundTrip) {
  LidarScan scan;
  scan.utime = 123456;
  scan.seq = 7;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2 * M_PI / 4;
  scan.range_min_m = 0.15;
  scan.range_max_m = 12.0;
  scan.range_m = {1.0f, 0.0f, 11.5f, 3.25f};
  const auto back = FromLcm(WireRoundTrip(ToLcm(scan)));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->utime, 123456);
  EXPECT_EQ(back->seq, 7);
  EXPECT_EQ(back->range_m, scan.range_m);
  EXPECT_FLOAT_EQ(back->angle_increment_rad, static_cast<float>(M_PI / 2));
  EXPECT_TRUE(back->IsValidReturn(0));
  EXPECT_FALSE(back->IsValidReturn(1));  // 0 = no return
}

TEST(TypesLcm, LidarScanWithBrokenGeometryIsRejected) {
  LidarScan scan;
  scan.range_min_m = 1.0;
  scan.range_max_m = 0.5;
  EXPECT_FALSE(FromLcm(ToLcm(scan)).has_value());
  scan.range_max_m = 12.0;
  scan.angle_increment_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(FromLcm(ToLcm(scan)).has_value());
}

TEST(TypesLcm, OdometryAndCommandRejectNonFinite) {
  Odometry odometry{10, 1, {1.0, 2.0, 0.5}, 0.2, -0.1};
  const auto back = FromLcm(WireRoundTrip(ToLcm(odometry)));
  ASSERT_TRUE(back.has_value());
  EXPECT_DOUBLE_EQ(back->pose.y_m, 2.0);
  EXPECT_DOUBLE_EQ(back->angular_velocity_radps, -0.1);
  odometry.pose.x_m = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(FromLcm(ToLcm(odometry)).has_value());

  VelocityCommand command{5, 0.3, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_FALSE(FromLcm(ToLcm(command)).has_value());
  command.angular_radps = 0.7;
  EXPECT_DOUBLE_EQ(FromLcm(WireRoundTrip(ToLcm(command)))->angular_radps, 0.7);
}

TEST(TypesLcm, OccupancyGridRoundTripAndValidation) {
  OccupancyGrid grid(3, 2, 0.05, {-1.0, 2.0});
  grid.at({2, 1}) = 100;
  grid.at({0, 0}) = 0;
  occupancy_grid_t msg = WireRoundTrip(ToLcm(grid, 99, 4, "map"));
  EXPECT_EQ(msg.frame, "map");
  EXPECT_EQ(msg.revision, 4);
  const auto back = FromLcm(msg);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->cells(), grid.cells());
  EXPECT_DOUBLE_EQ(back->origin_m().x_m, -1.0);

  occupancy_grid_t wrong_size = msg;
  wrong_size.width_cells = 4;
  EXPECT_FALSE(FromLcm(wrong_size).has_value());
  occupancy_grid_t bad_value = msg;
  bad_value.cells[1] = 101;
  EXPECT_FALSE(FromLcm(bad_value).has_value());
  occupancy_grid_t rotated = msg;
  rotated.origin.yaw_rad = 0.1;
  EXPECT_FALSE(FromLcm(rotated).has_value());
}

}  // namespace
}  // namespace aslam
