#include "common/robot_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ErrorOf(const std::string& yaml) {
  return ConfigErrorOf(LoadRobotOptions, yaml, "robot");
}

TEST(RobotConfig, ShippedConfigHoldsTheDefaults) {
  const RobotOptions shipped = LoadRobotOptionsFromFile(ShippedConfigPath());
  const RobotOptions defaults;
  EXPECT_DOUBLE_EQ(shipped.radius_m, 0.20);
  EXPECT_DOUBLE_EQ(shipped.radius_m, defaults.radius_m);
  EXPECT_DOUBLE_EQ(shipped.clearance_margin_m, defaults.clearance_margin_m);
  EXPECT_DOUBLE_EQ(shipped.max_linear_mps, defaults.max_linear_mps);
  EXPECT_DOUBLE_EQ(shipped.max_angular_radps, defaults.max_angular_radps);
  EXPECT_DOUBLE_EQ(shipped.max_linear_accel_mps2, defaults.max_linear_accel_mps2);
  EXPECT_DOUBLE_EQ(shipped.max_angular_accel_radps2, defaults.max_angular_accel_radps2);
  // The simulated lidar sits at the base centre: scans are cast from the base pose.
  EXPECT_EQ(shipped.lidar_mount.x_m, 0.0);
  EXPECT_EQ(shipped.lidar_mount.y_m, 0.0);
  EXPECT_EQ(shipped.lidar_mount.yaw_rad, 0.0);
}

TEST(RobotConfig, NoFileGivesTheDefaults) {
  EXPECT_DOUBLE_EQ(LoadRobotOptionsFromFile("").radius_m, RobotOptions{}.radius_m);
}

TEST(RobotConfig, ReadsEveryKey) {
  const RobotOptions o = LoadRobotOptions(ConfigReader::FromString(
      "robot:\n  radius_m: 0.3\n  clearance_margin_m: 0.1\n  max_linear_mps: 0.8\n"
      "  max_angular_radps: 2.0\n  max_linear_accel_mps2: 1.5\n  max_angular_accel_radps2: 4.0\n"
      "  lidar_mount: {x_m: 0.1, y_m: -0.05, yaw_rad: 3.14}\n",
      "robot"));
  EXPECT_DOUBLE_EQ(o.radius_m, 0.3);
  EXPECT_DOUBLE_EQ(o.clearance_margin_m, 0.1);
  EXPECT_DOUBLE_EQ(o.max_linear_mps, 0.8);
  EXPECT_DOUBLE_EQ(o.max_angular_radps, 2.0);
  EXPECT_DOUBLE_EQ(o.max_linear_accel_mps2, 1.5);
  EXPECT_DOUBLE_EQ(o.max_angular_accel_radps2, 4.0);
  EXPECT_DOUBLE_EQ(o.lidar_mount.x_m, 0.1);
  EXPECT_DOUBLE_EQ(o.lidar_mount.y_m, -0.05);
  EXPECT_DOUBLE_EQ(o.lidar_mount.yaw_rad, 3.14);
}

TEST(RobotConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(ErrorOf("robot:\n  radius_m: 0\n"),
              AllOf(HasSubstr("test.yaml:2"), HasSubstr("robot.radius_m"), HasSubstr("'0'")));
  EXPECT_THAT(
      ErrorOf("robot:\n  clearance_margin_m: -0.05\n"),
      AllOf(HasSubstr("test.yaml:2"), HasSubstr("robot.clearance_margin_m"), HasSubstr("'-0.05'")));
  EXPECT_THAT(ErrorOf("robot:\n  max_linear_mps: fast\n"),
              AllOf(HasSubstr("robot.max_linear_mps"), HasSubstr("'fast'"), HasSubstr("number")));
  EXPECT_THAT(ErrorOf("robot:\n  max_angular_accel_radps2: 0\n"),
              AllOf(HasSubstr("robot.max_angular_accel_radps2"), HasSubstr("'0'")));
  EXPECT_THAT(
      ErrorOf("robot:\n  lidar_mount:\n    yaw_rad: 4\n"),
      AllOf(HasSubstr("test.yaml:3"), HasSubstr("robot.lidar_mount.yaw_rad"), HasSubstr("'4'")));
  EXPECT_THAT(ErrorOf("robot:\n  lidar_mount: {x_m: 0.3}\n"),
              AllOf(HasSubstr("robot.lidar_mount.x_m"), HasSubstr("'0.3'"), HasSubstr("radius_m")));
  EXPECT_THAT(ErrorOf("robot:\n  lidar_mount: {z_m: 0.3}\n"),
              AllOf(HasSubstr("robot.lidar_mount.z_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("robot:\n  robot_radius_m: 0.2\n"),
              AllOf(HasSubstr("robot.robot_radius_m"), HasSubstr("unknown key")));
}

}  // namespace
}  // namespace aslam
