#include "frontier/frontier_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kShippedConfig = ShippedConfigPath();

std::string ErrorOf(const std::string& yaml) {
  return ConfigErrorOf([](const ConfigReader& c) { return LoadFrontierOptions(c, NavOptions{}); },
                       yaml, "frontier");
}

TEST(FrontierConfig, ShippedConfigLoadsAndHoldsTheDefaults) {
  const FrontierOptions shipped = LoadFrontierOptionsFromFile(kShippedConfig);
  const FrontierOptions defaults;
  EXPECT_EQ(shipped.free_threshold, 0);
  EXPECT_EQ(shipped.free_threshold, defaults.free_threshold);
  EXPECT_DOUBLE_EQ(shipped.min_size_m, defaults.min_size_m);
  EXPECT_DOUBLE_EQ(shipped.max_segment_length_m, defaults.max_segment_length_m);
  EXPECT_DOUBLE_EQ(shipped.target_radius_m, defaults.target_radius_m);
  EXPECT_DOUBLE_EQ(shipped.target_clearance_m, defaults.target_clearance_m);
  EXPECT_DOUBLE_EQ(shipped.match_distance_m, defaults.match_distance_m);
  EXPECT_DOUBLE_EQ(shipped.costmap.robot_radius_m, 0.2);
  EXPECT_DOUBLE_EQ(shipped.costmap.clearance_margin_m, defaults.costmap.clearance_margin_m);
  EXPECT_EQ(shipped.costmap.occupied_threshold, defaults.costmap.occupied_threshold);
  EXPECT_EQ(shipped.costmap.unknown_passable, defaults.costmap.unknown_passable);
  EXPECT_DOUBLE_EQ(shipped.global_planner.start_escape_m, defaults.global_planner.start_escape_m);
}

// "Reachable" means what the navigator will plan: its costmap and planner, robot included.
TEST(FrontierConfig, PlansOnTheNavigatorsCostmapAndPlanner) {
  const std::string file =
      WriteTestConfig("frontier_nav.yaml",
                      "robot: {radius_m: 0.25, clearance_margin_m: 0.08}\n"
                      "nav:\n  costmap: {occupied_threshold: 70, unknown_passable: false, "
                      "inflation_margin_m: 0.3}\n"
                      "  global_planner: {start_escape_m: 0.4, cost_weight: 2.0}\n"
                      "frontier: {min_size_m: 0.3}\n");
  const FrontierOptions o = LoadFrontierOptionsFromFile(file);
  const NavOptions nav = LoadNavOptionsFromFile(file);
  EXPECT_DOUBLE_EQ(o.min_size_m, 0.3);
  EXPECT_DOUBLE_EQ(o.costmap.robot_radius_m, 0.25);
  EXPECT_DOUBLE_EQ(o.costmap.clearance_margin_m, 0.08);
  EXPECT_EQ(o.costmap.occupied_threshold, 70);
  EXPECT_FALSE(o.costmap.unknown_passable);
  EXPECT_DOUBLE_EQ(o.costmap.inflation_margin_m, nav.costmap.inflation_margin_m);
  EXPECT_DOUBLE_EQ(o.costmap.cost_scaling_per_m, nav.costmap.cost_scaling_per_m);
  EXPECT_EQ(o.costmap.unknown_cost, nav.costmap.unknown_cost);
  EXPECT_DOUBLE_EQ(o.global_planner.start_escape_m, 0.4);
  EXPECT_DOUBLE_EQ(o.global_planner.cost_weight, nav.global_planner.cost_weight);
}

TEST(FrontierConfig, ReadsEveryKey) {
  const FrontierOptions o = LoadFrontierOptions(
      ConfigReader::FromString(
          "frontier:\n  free_threshold: 10\n  min_size_m: 0.3\n  max_segment_length_m: 3.0\n"
          "  target_radius_m: 0.5\n  target_clearance_m: 0.1\n  match_distance_m: 0.7\n",
          "frontier"),
      NavOptions{});
  EXPECT_EQ(o.free_threshold, 10);
  EXPECT_DOUBLE_EQ(o.min_size_m, 0.3);
  EXPECT_DOUBLE_EQ(o.max_segment_length_m, 3.0);
  EXPECT_DOUBLE_EQ(o.target_radius_m, 0.5);
  EXPECT_DOUBLE_EQ(o.target_clearance_m, 0.1);
  EXPECT_DOUBLE_EQ(o.match_distance_m, 0.7);
}

TEST(FrontierConfig, EmptyFileNameGivesDefaults) {
  EXPECT_DOUBLE_EQ(LoadFrontierOptionsFromFile("").max_segment_length_m, 2.5);
  EXPECT_DOUBLE_EQ(LoadFrontierOptionsFromFile("").costmap.robot_radius_m, 0.2);
}

TEST(FrontierConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(ErrorOf("frontier:\n  min_size_m: -1\n"),
              AllOf(HasSubstr("test.yaml:2"), HasSubstr("frontier.min_size_m"), HasSubstr("'-1'")));
  EXPECT_THAT(ErrorOf("frontier:\n  target_clearance_m: -0.1\n"),
              AllOf(HasSubstr("frontier.target_clearance_m"), HasSubstr("'-0.1'")));
  EXPECT_THAT(ErrorOf("frontier:\n  max_segment_m: 2\n"),
              AllOf(HasSubstr("frontier.max_segment_m"), HasSubstr("unknown key")));
  // The costmap, planner and robot radius are nav's and the robot's: here they are typos.
  EXPECT_THAT(ErrorOf("frontier:\n  costmap: {unknown_passable: true}\n"),
              AllOf(HasSubstr("frontier.costmap"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("frontier:\n  robot_radius_m: 0.2\n"),
              AllOf(HasSubstr("frontier.robot_radius_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("frontier:\n  free_threshold: 70\n"),
              AllOf(HasSubstr("frontier.free_threshold"), HasSubstr("'70'"),
                    HasSubstr("nav.costmap.occupied_threshold")));
  EXPECT_THAT(ErrorOf("frontier:\n  max_segment_length_m: 0.4\n"),
              AllOf(HasSubstr("frontier.max_segment_length_m"), HasSubstr("min_size_m")));
}

TEST(FrontierConfig, BadRobotOrNavKeysNameFileKeyAndValue) {
  const std::string robot = WriteTestConfig("frontier_bad_robot.yaml", "robot:\n  radius_m: 0\n");
  EXPECT_THAT(
      ConfigErrorOf([&] { LoadFrontierOptionsFromFile(robot); }),
      AllOf(HasSubstr("frontier_bad_robot.yaml:2"), HasSubstr("robot.radius_m"), HasSubstr("'0'")));
  const std::string nav =
      WriteTestConfig("frontier_bad_nav.yaml", "nav:\n  costmap:\n    unknown_passable: maybe\n");
  EXPECT_THAT(ConfigErrorOf([&] { LoadFrontierOptionsFromFile(nav); }),
              AllOf(HasSubstr("frontier_bad_nav.yaml:3"), HasSubstr("nav.costmap.unknown_passable"),
                    HasSubstr("'maybe'")));
}

}  // namespace
}  // namespace aslam
