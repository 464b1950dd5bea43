#include "drivers/sim/sim_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

SimulatorOptions Load(const std::string& yaml) {
  return LoadSimulatorOptions(ConfigReader::FromString(yaml, "sim"), RobotOptions{});
}

std::string ErrorOf(const std::string& yaml) {
  return ConfigErrorOf(
      [](const ConfigReader& sim) { return LoadSimulatorOptions(sim, RobotOptions{}); }, yaml,
      "sim");
}

TEST(SimConfig, DefaultsAreTheIssueSpecification) {
  const SimulatorOptions options = Load("");
  EXPECT_EQ(options.lidar.num_beams, 720);
  EXPECT_DOUBLE_EQ(options.lidar.rate_hz, 10.0);
  EXPECT_DOUBLE_EQ(options.lidar.range_min_m, 0.15);
  EXPECT_DOUBLE_EQ(options.lidar.range_max_m, 12.0);
  EXPECT_DOUBLE_EQ(options.lidar.noise_sigma_m, 0.01);
  EXPECT_DOUBLE_EQ(options.lidar.noise_sigma_fraction, 0.005);
  EXPECT_DOUBLE_EQ(options.robot.radius_m, 0.20);
  EXPECT_DOUBLE_EQ(options.robot.max_linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(options.robot.max_angular_radps, 1.8);
  EXPECT_DOUBLE_EQ(options.robot.max_linear_accel_mps2, 1.0);
  EXPECT_DOUBLE_EQ(options.command_timeout_s, 0.5);
  const SimulatorOptions shipped = LoadSimulatorOptionsFromFile(ShippedConfigPath());
  EXPECT_EQ(shipped.lidar.num_beams, options.lidar.num_beams);
  EXPECT_DOUBLE_EQ(shipped.robot.radius_m, options.robot.radius_m);
  EXPECT_DOUBLE_EQ(LoadSimulatorOptionsFromFile("").robot.radius_m, 0.20);
}

// The simulated base and lidar mount are the robot section's, read from the same file.
TEST(SimConfig, TheRobotSectionIsTheSimulatedRobot) {
  const std::string file =
      WriteTestConfig("sim_robot.yaml",
                      "robot:\n  radius_m: 0.3\n  max_linear_mps: 0.7\n  max_angular_radps: 1.2\n"
                      "  max_linear_accel_mps2: 0.8\n  max_angular_accel_radps2: 2.5\n"
                      "  lidar_mount: {x_m: 0.1, y_m: -0.05, yaw_rad: 0.5}\nsim:\n  seed: 7\n");
  const SimulatorOptions options = LoadSimulatorOptionsFromFile(file);
  EXPECT_EQ(options.seed, 7u);
  EXPECT_DOUBLE_EQ(options.robot.radius_m, 0.3);
  EXPECT_DOUBLE_EQ(options.robot.max_linear_mps, 0.7);
  EXPECT_DOUBLE_EQ(options.robot.max_angular_radps, 1.2);
  EXPECT_DOUBLE_EQ(options.robot.max_linear_accel_mps2, 0.8);
  EXPECT_DOUBLE_EQ(options.robot.max_angular_accel_radps2, 2.5);
  EXPECT_DOUBLE_EQ(options.robot.lidar_mount.x_m, 0.1);
  EXPECT_DOUBLE_EQ(options.robot.lidar_mount.y_m, -0.05);
  EXPECT_DOUBLE_EQ(options.robot.lidar_mount.yaw_rad, 0.5);
}

TEST(SimConfig, BadRobotKeysNameFileKeyAndValue) {
  const std::string file =
      WriteTestConfig("sim_bad_robot.yaml", "robot:\n  radius_m: fat\nsim: {}\n");
  EXPECT_THAT(
      ConfigErrorOf([&] { LoadSimulatorOptionsFromFile(file); }),
      AllOf(HasSubstr("sim_bad_robot.yaml:2"), HasSubstr("robot.radius_m"), HasSubstr("'fat'")));
}

TEST(SimConfig, ReadsNestedSections) {
  const SimulatorOptions options = Load(
      "sim:\n  seed: 42\n  lidar: {num_beams: 360, range_max_m: 8}\n"
      "  odometry_noise: {alpha3: 0.5}\n");
  EXPECT_EQ(options.seed, 42u);
  EXPECT_EQ(options.lidar.num_beams, 360);
  EXPECT_DOUBLE_EQ(options.lidar.range_max_m, 8.0);
  EXPECT_DOUBLE_EQ(options.odometry_noise.alpha3, 0.5);
}

TEST(SimConfig, ALidarModelSetsTheSensorAndKeysBesideItOverride) {
  const SimulatorOptions a1 = Load("sim:\n  lidar: {model: rplidar_a1}\n");
  EXPECT_EQ(a1.lidar.model, "rplidar_a1");
  EXPECT_EQ(a1.lidar.rate_hz, 5.5);
  EXPECT_TRUE(a1.lidar.swept);
  EXPECT_TRUE(a1.lidar.clockwise);
  const SimulatorOptions urg = Load("sim:\n  lidar: {model: hokuyo_urg04, range_max_m: 4.0}\n");
  EXPECT_EQ(urg.lidar.num_beams, 682);
  EXPECT_LT(urg.lidar.fov_rad, 2.0 * M_PI);
  EXPECT_EQ(urg.lidar.range_max_m, 4.0);
  EXPECT_FALSE(Load("").lidar.swept);  // the shipped default is the ideal sensor
  EXPECT_THAT(ErrorOf("sim:\n  lidar: {model: sick_lms}\n"),
              AllOf(HasSubstr("sim.lidar.model"), HasSubstr("sick_lms"), HasSubstr("rplidar_a1")));
}

TEST(SimConfig, BadValuesNameKeyAndValue) {
  EXPECT_THAT(ErrorOf("sim:\n  lidar:\n    num_beams: 0\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("sim.lidar.num_beams"), HasSubstr("'0'")));
  EXPECT_THAT(ErrorOf("sim:\n  lidar: {range_min_m: 5, range_max_m: 4}\n"),
              AllOf(HasSubstr("sim.lidar.range_min_m"), HasSubstr("below range_max_m")));
  EXPECT_THAT(
      ErrorOf("sim:\n  lidar: {rate_hz: 40}\n"),
      AllOf(HasSubstr("test.yaml"), HasSubstr("lidar.rate_hz = 40"), HasSubstr("physics_rate_hz")));
  // The base is the robot section's now: a leftover sim.base is a typo.
  EXPECT_THAT(ErrorOf("sim:\n  base: {radius_m: 0.2}\n"),
              AllOf(HasSubstr("sim.base"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("sim:\n  odometry_noise: {alpha5: 1}\n"),
              AllOf(HasSubstr("sim.odometry_noise.alpha5"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("sim:\n  physics_rate_hz: 300\n"), HasSubstr("physics_rate_hz = 300"));
  EXPECT_THAT(ErrorOf("sim:\n  seed: -1\n"), HasSubstr("sim.seed"));
}

}  // namespace
}  // namespace aslam
