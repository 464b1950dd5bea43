#include "drivers/sim/sim_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ErrorOf(const std::string& yaml) {
  try {
    LoadSimulatorOptions(ConfigReader::FromString(yaml, "sim", "test.yaml"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SimConfig, DefaultsAreTheIssueSpecification) {
  const SimulatorOptions options = LoadSimulatorOptions(ConfigReader::FromString("", "sim"));
  EXPECT_EQ(options.lidar.num_beams, 720);
  EXPECT_DOUBLE_EQ(options.lidar.rate_hz, 10.0);
  EXPECT_DOUBLE_EQ(options.lidar.range_min_m, 0.15);
  EXPECT_DOUBLE_EQ(options.lidar.range_max_m, 12.0);
  EXPECT_DOUBLE_EQ(options.lidar.noise_sigma_m, 0.01);
  EXPECT_DOUBLE_EQ(options.lidar.noise_sigma_fraction, 0.005);
  EXPECT_DOUBLE_EQ(options.base.radius_m, 0.20);
  EXPECT_DOUBLE_EQ(options.base.max_linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(options.base.max_angular_radps, 1.8);
  EXPECT_DOUBLE_EQ(options.base.max_linear_accel_mps2, 1.0);
  EXPECT_DOUBLE_EQ(options.command_timeout_s, 0.5);
}

TEST(SimConfig, ReadsNestedSections) {
  const SimulatorOptions options = LoadSimulatorOptions(ConfigReader::FromString(
      "sim:\n  seed: 42\n  lidar: {num_beams: 360, range_max_m: 8}\n"
      "  base: {radius_m: 0.3}\n  odometry_noise: {alpha3: 0.5}\n",
      "sim"));
  EXPECT_EQ(options.seed, 42u);
  EXPECT_EQ(options.lidar.num_beams, 360);
  EXPECT_DOUBLE_EQ(options.lidar.range_max_m, 8.0);
  EXPECT_DOUBLE_EQ(options.base.radius_m, 0.3);
  EXPECT_DOUBLE_EQ(options.odometry_noise.alpha3, 0.5);
}

TEST(SimConfig, BadValuesNameKeyAndValue) {
  EXPECT_THAT(ErrorOf("sim:\n  lidar:\n    num_beams: 0\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("sim.lidar.num_beams"), HasSubstr("'0'")));
  EXPECT_THAT(ErrorOf("sim:\n  lidar: {range_min_m: 5, range_max_m: 4}\n"),
              AllOf(HasSubstr("sim.lidar.range_min_m"), HasSubstr("below range_max_m")));
  EXPECT_THAT(ErrorOf("sim:\n  lidar: {rate_hz: 40}\n"),
              AllOf(HasSubstr("test.yaml"), HasSubstr("lidar.rate_hz = 40"), HasSubstr("physics_rate_hz")));
  EXPECT_THAT(ErrorOf("sim:\n  base: {radius_m: fat}\n"),
              AllOf(HasSubstr("sim.base.radius_m"), HasSubstr("'fat'"), HasSubstr("number")));
  EXPECT_THAT(ErrorOf("sim:\n  odometry_noise: {alpha5: 1}\n"),
              AllOf(HasSubstr("sim.odometry_noise.alpha5"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("sim:\n  physics_rate_hz: 300\n"), HasSubstr("physics_rate_hz = 300"));
  EXPECT_THAT(ErrorOf("sim:\n  seed: -1\n"), HasSubstr("sim.seed"));
}

}  // namespace
}  // namespace aslam
