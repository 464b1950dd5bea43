// The `kobuki:` section: values, limits from the `robot:` section, errors naming the key.

#include <gtest/gtest.h>

#include "common/config_testing.h"
#include "drivers/kobuki/kobuki_driver.h"

namespace aslam {
namespace {

TEST(KobukiOptions, TheShippedConfigLoadsWithTheRobotsLimits) {
  const KobukiOptions o = LoadKobukiOptionsFromFile(ShippedConfigPath());
  EXPECT_EQ(o.port, "/dev/kobuki");
  EXPECT_TRUE(o.gyro_heading);
  EXPECT_DOUBLE_EQ(o.safety.command_timeout_s, 0.5);
  const std::string file = WriteTestConfig(
      "kobuki_limits.yaml",
      "robot:\n  max_linear_mps: 0.3\n  max_angular_accel_radps2: 2.0\n"
      "kobuki:\n  port: /dev/ttyUSB3\n  heading: encoders\n  reconnect_backoff_s: [1, 4]\n");
  const KobukiOptions custom = LoadKobukiOptionsFromFile(file);
  EXPECT_EQ(custom.port, "/dev/ttyUSB3");
  EXPECT_FALSE(custom.gyro_heading);
  EXPECT_DOUBLE_EQ(custom.safety.max_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(custom.safety.max_angular_accel_radps2, 2.0);
  EXPECT_DOUBLE_EQ(custom.reconnect_backoff_initial_s, 1.0);
  EXPECT_DOUBLE_EQ(custom.reconnect_backoff_max_s, 4.0);
}

TEST(KobukiOptions, ErrorsNameTheFileTheKeyAndTheValue) {
  const auto error_of = [](const std::string& yaml) {
    return ConfigErrorOf(
        [&] { LoadKobukiOptions(ConfigReader::FromString(yaml, "kobuki", "base.yaml")); });
  };
  const std::string heading = error_of("kobuki:\n  heading: compass\n");
  EXPECT_NE(heading.find("base.yaml"), std::string::npos) << heading;
  EXPECT_NE(heading.find("kobuki.heading"), std::string::npos) << heading;
  EXPECT_NE(heading.find("compass"), std::string::npos) << heading;
  EXPECT_NE(error_of("kobuki:\n  wheel_radius_m: 0\n").find("wheel_radius_m"), std::string::npos);
  EXPECT_NE(error_of("kobuki:\n  command_timeout: 1\n").find("command_timeout"), std::string::npos);
  EXPECT_NE(error_of("kobuki:\n  reconnect_backoff_s: [4, 1]\n").find("reconnect_backoff_s"),
            std::string::npos);
  KobukiOptions empty_port;
  empty_port.port = "";
  EXPECT_THROW(ValidateKobukiOptions(empty_port), std::invalid_argument);
}

}  // namespace
}  // namespace aslam
