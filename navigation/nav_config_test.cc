#include "navigation/nav_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kShippedConfig = ShippedConfigPath();

NavOptions Load(const std::string& yaml) {
  return LoadNavOptions(ConfigReader::FromString(yaml, "nav"), RobotOptions{});
}

std::string ErrorOf(const std::string& yaml) {
  return ConfigErrorOf([](const ConfigReader& c) { return LoadNavOptions(c, RobotOptions{}); },
                       yaml, "nav");
}

TEST(NavConfig, ShippedConfigLoadsAndHoldsTheDefaults) {
  const NavOptions shipped = LoadNavOptionsFromFile(kShippedConfig);
  const NavOptions defaults;
  EXPECT_DOUBLE_EQ(shipped.navigator.goal_tolerance_m, 0.3);
  EXPECT_DOUBLE_EQ(shipped.navigator.goal_tolerance_m, defaults.navigator.goal_tolerance_m);
  EXPECT_DOUBLE_EQ(shipped.navigator.replan_period_s, defaults.navigator.replan_period_s);
  EXPECT_DOUBLE_EQ(shipped.navigator.progress_timeout_s, defaults.navigator.progress_timeout_s);
  EXPECT_EQ(shipped.navigator.max_recoveries, defaults.navigator.max_recoveries);
  EXPECT_DOUBLE_EQ(shipped.navigator.squeeze_margin_m, defaults.navigator.squeeze_margin_m);
  EXPECT_DOUBLE_EQ(shipped.navigator.scan_mark_clear_margin_m,
                   defaults.navigator.scan_mark_clear_margin_m);
  EXPECT_DOUBLE_EQ(shipped.navigator.recovery.back_off_distance_m,
                   defaults.navigator.recovery.back_off_distance_m);
  EXPECT_DOUBLE_EQ(shipped.costmap.robot_radius_m, defaults.costmap.robot_radius_m);
  EXPECT_DOUBLE_EQ(shipped.costmap.inflation_margin_m, defaults.costmap.inflation_margin_m);
  EXPECT_EQ(shipped.costmap.unknown_cost, defaults.costmap.unknown_cost);
  EXPECT_DOUBLE_EQ(shipped.global_planner.cost_weight, defaults.global_planner.cost_weight);
  EXPECT_DOUBLE_EQ(shipped.local_obstacles.window_m, defaults.local_obstacles.window_m);
  EXPECT_DOUBLE_EQ(shipped.dwa.horizon_s, 2.0);
  EXPECT_DOUBLE_EQ(shipped.dwa.max_linear_mps, defaults.dwa.max_linear_mps);
  EXPECT_DOUBLE_EQ(shipped.dwa.goal_lookahead_m, defaults.dwa.goal_lookahead_m);
  EXPECT_EQ(shipped.dwa.angular_samples, defaults.dwa.angular_samples);
  EXPECT_DOUBLE_EQ(shipped.dwa.weight_path_alignment, defaults.dwa.weight_path_alignment);
  EXPECT_DOUBLE_EQ(shipped.dwa.weight_goal_heading, defaults.dwa.weight_goal_heading);
  EXPECT_DOUBLE_EQ(shipped.dwa.weight_clearance, defaults.dwa.weight_clearance);
  EXPECT_DOUBLE_EQ(shipped.dwa.weight_speed, defaults.dwa.weight_speed);
  EXPECT_EQ(shipped.dwa.escape_inside_margin, defaults.dwa.escape_inside_margin);
}

TEST(NavConfig, EmptyFileNameGivesDefaults) {
  EXPECT_DOUBLE_EQ(LoadNavOptionsFromFile("").navigator.goal_tolerance_m, 0.3);
}

TEST(NavConfig, ReadsNestedSections) {
  const NavOptions options = Load(
      "nav:\n  max_recoveries: 5\n  recovery: {back_off_speed_mps: 0.2}\n"
      "  costmap: {unknown_passable: false}\n  dwa: {angular_samples: 31}\n");
  EXPECT_EQ(options.navigator.max_recoveries, 5);
  EXPECT_DOUBLE_EQ(options.navigator.recovery.back_off_speed_mps, 0.2);
  EXPECT_FALSE(options.costmap.unknown_passable);
  EXPECT_EQ(options.dwa.angular_samples, 31);
}

// One radius and one margin for the planner's inscribed zone and the DWA's
// collision circle, and the DWA's window is the robot's limits.
TEST(NavConfig, TheRobotSectionReachesCostmapAndDwa) {
  const std::string file = WriteTestConfig(
      "nav_robot.yaml",
      "robot:\n  radius_m: 0.3\n  clearance_margin_m: 0.02\n  max_linear_mps: 0.4\n"
      "  max_angular_radps: 1.2\n  max_linear_accel_mps2: 0.8\n  max_angular_accel_radps2: 2.5\n"
      "nav: {goal_tolerance_m: 0.4}\n");
  const NavOptions options = LoadNavOptionsFromFile(file);
  EXPECT_DOUBLE_EQ(options.navigator.goal_tolerance_m, 0.4);
  EXPECT_DOUBLE_EQ(options.costmap.robot_radius_m, 0.3);
  EXPECT_DOUBLE_EQ(options.dwa.robot_radius_m, 0.3);
  EXPECT_DOUBLE_EQ(options.costmap.clearance_margin_m, 0.02);
  EXPECT_DOUBLE_EQ(options.dwa.safety_margin_m, 0.02);
  EXPECT_DOUBLE_EQ(options.dwa.max_linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(options.dwa.max_angular_radps, 1.2);
  EXPECT_DOUBLE_EQ(options.dwa.max_linear_accel_mps2, 0.8);
  EXPECT_DOUBLE_EQ(options.dwa.max_angular_accel_radps2, 2.5);
}

TEST(NavConfig, BadRobotKeysNameFileKeyAndValue) {
  const std::string file =
      WriteTestConfig("nav_bad_robot.yaml", "robot:\n  max_linear_mps: -1\nnav: {}\n");
  EXPECT_THAT(ConfigErrorOf([&] { LoadNavOptionsFromFile(file); }),
              AllOf(HasSubstr("nav_bad_robot.yaml:2"), HasSubstr("robot.max_linear_mps"),
                    HasSubstr("'-1'")));
  // A robot too fast for the local window is reported against the window.
  RobotOptions fast;
  fast.max_linear_mps = 3.0;
  EXPECT_THAT(ConfigErrorOf([&] { LoadNavOptions(ConfigReader::FromString("", "nav"), fast); }),
              AllOf(HasSubstr("nav.local_obstacles.window_m"), HasSubstr("robot.max_linear_mps")));
}

TEST(NavConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(
      ErrorOf("nav:\n  goal_tolerance_m: -1\n"),
      AllOf(HasSubstr("test.yaml:2"), HasSubstr("nav.goal_tolerance_m"), HasSubstr("'-1'")));
  EXPECT_THAT(ErrorOf("nav:\n  dwa:\n    horizon_s: soon\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("nav.dwa.horizon_s"), HasSubstr("'soon'")));
  // The radius, margins and limits are the robot section's: here they are typos.
  EXPECT_THAT(ErrorOf("nav:\n  costmap:\n    clearance_margin_m: 0.05\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("nav.costmap.clearance_margin_m"),
                    HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("nav:\n  dwa: {safety_margin_m: 0.05}\n"),
              AllOf(HasSubstr("nav.dwa.safety_margin_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("nav:\n  dwa: {max_linear_mps: 0.5}\n"),
              AllOf(HasSubstr("nav.dwa.max_linear_mps"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("nav:\n  robot_radius_m: 0.2\n"),
              AllOf(HasSubstr("nav.robot_radius_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("nav:\n  dwa: {max_speed: 1}\n"),
              AllOf(HasSubstr("nav.dwa.max_speed"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("nav:\n  recovery: {back_off_speed_mps: 0}\n"),
              HasSubstr("nav.recovery.back_off_speed_mps"));
  EXPECT_THAT(ErrorOf("nav:\n  costmap: {unknown_cost: 300}\n"),
              AllOf(HasSubstr("nav.costmap.unknown_cost"), HasSubstr("'300'")));
  EXPECT_THAT(ErrorOf("nav:\n  goal_snap_m: -0.1\n"),
              AllOf(HasSubstr("nav.goal_snap_m"), HasSubstr("'-0.1'")));
  EXPECT_THAT(ErrorOf("nav:\n  align_start_rad: 0.2\n"),
              AllOf(HasSubstr("nav.align_done_rad"), HasSubstr("align_start_rad")));
  EXPECT_THAT(ErrorOf("nav:\n  dwa: {min_linear_mps: 0.6}\n"),
              AllOf(HasSubstr("nav.dwa.min_linear_mps"), HasSubstr("robot.max_linear_mps")));
  EXPECT_THAT(ErrorOf("nav:\n  scan_mark_clear_margin_m: 0\n"),
              AllOf(HasSubstr("nav.scan_mark_clear_margin_m"), HasSubstr("'0'")));
  EXPECT_THAT(ErrorOf("nav:\n  squeeze_margin_m: 0.08\n"),
              AllOf(HasSubstr("nav.squeeze_margin_m"), HasSubstr("robot.clearance_margin_m")));
  // Cross-section: the local window must hold the DWA's longest rollout.
  EXPECT_THAT(ErrorOf("nav:\n  dwa: {horizon_s: 10}\n"),
              AllOf(HasSubstr("nav.local_obstacles.window_m"), HasSubstr("horizon_s")));
  // A check only the component makes, reported against its section.
  EXPECT_THAT(
      ErrorOf("nav:\n  local_obstacles: {window_m: 100, resolution_m: 0.005}\n"),
      AllOf(HasSubstr("test.yaml"), HasSubstr("nav.local_obstacles"), HasSubstr("window_m")));
}

}  // namespace
}  // namespace aslam
