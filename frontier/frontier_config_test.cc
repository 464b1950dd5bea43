#include "frontier/frontier_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"
#include "navigation/nav_config.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kShippedConfig = ShippedConfigPath();

std::string ErrorOf(const std::string& yaml) { return ConfigErrorOf(LoadFrontierOptions, yaml, "frontier"); }

TEST(FrontierConfig, ShippedConfigLoadsAndHoldsTheDefaults) {
  const FrontierOptions shipped = LoadFrontierOptionsFromFile(kShippedConfig);
  const FrontierOptions defaults;
  EXPECT_EQ(shipped.free_threshold, 0);
  EXPECT_EQ(shipped.free_threshold, defaults.free_threshold);
  EXPECT_DOUBLE_EQ(shipped.min_size_m, defaults.min_size_m);
  EXPECT_DOUBLE_EQ(shipped.max_segment_length_m, defaults.max_segment_length_m);
  EXPECT_DOUBLE_EQ(shipped.target_radius_m, defaults.target_radius_m);
  EXPECT_DOUBLE_EQ(shipped.match_distance_m, defaults.match_distance_m);
  EXPECT_DOUBLE_EQ(shipped.costmap.robot_radius_m, 0.2);
  EXPECT_DOUBLE_EQ(shipped.costmap.clearance_margin_m, defaults.costmap.clearance_margin_m);
  EXPECT_EQ(shipped.costmap.occupied_threshold, defaults.costmap.occupied_threshold);
  EXPECT_EQ(shipped.costmap.unknown_passable, defaults.costmap.unknown_passable);
  EXPECT_DOUBLE_EQ(shipped.global_planner.start_escape_m, defaults.global_planner.start_escape_m);
}

// "Reachable" must mean what the navigator will plan: the same traversability.
TEST(FrontierConfig, ShippedCostmapMatchesTheNavigators) {
  const FrontierOptions frontier = LoadFrontierOptionsFromFile(kShippedConfig);
  const NavOptions nav = LoadNavOptionsFromFile(kShippedConfig);
  EXPECT_DOUBLE_EQ(frontier.costmap.robot_radius_m, nav.costmap.robot_radius_m);
  EXPECT_DOUBLE_EQ(frontier.costmap.clearance_margin_m, nav.costmap.clearance_margin_m);
  EXPECT_EQ(frontier.costmap.occupied_threshold, nav.costmap.occupied_threshold);
  EXPECT_EQ(frontier.costmap.unknown_passable, nav.costmap.unknown_passable);
  EXPECT_DOUBLE_EQ(frontier.global_planner.start_escape_m, nav.global_planner.start_escape_m);
}

TEST(FrontierConfig, ReadsEveryKey) {
  const FrontierOptions o = LoadFrontierOptions(ConfigReader::FromString(
      "frontier:\n  free_threshold: 10\n  min_size_m: 0.3\n  max_segment_length_m: 3.0\n"
      "  target_radius_m: 0.5\n  match_distance_m: 0.7\n  robot_radius_m: 0.25\n"
      "  costmap: {occupied_threshold: 70, unknown_passable: false}\n"
      "  global_planner: {start_escape_m: 0.4}\n",
      "frontier"));
  EXPECT_EQ(o.free_threshold, 10);
  EXPECT_DOUBLE_EQ(o.min_size_m, 0.3);
  EXPECT_DOUBLE_EQ(o.max_segment_length_m, 3.0);
  EXPECT_DOUBLE_EQ(o.target_radius_m, 0.5);
  EXPECT_DOUBLE_EQ(o.match_distance_m, 0.7);
  EXPECT_DOUBLE_EQ(o.costmap.robot_radius_m, 0.25);
  EXPECT_EQ(o.costmap.occupied_threshold, 70);
  EXPECT_FALSE(o.costmap.unknown_passable);
  EXPECT_DOUBLE_EQ(o.global_planner.start_escape_m, 0.4);
}

TEST(FrontierConfig, EmptyFileNameGivesDefaults) {
  EXPECT_DOUBLE_EQ(LoadFrontierOptionsFromFile("").max_segment_length_m, 2.5);
}

TEST(FrontierConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(ErrorOf("frontier:\n  min_size_m: -1\n"),
              AllOf(HasSubstr("test.yaml:2"), HasSubstr("frontier.min_size_m"), HasSubstr("'-1'")));
  EXPECT_THAT(ErrorOf("frontier:\n  costmap:\n    unknown_passable: maybe\n"),
              AllOf(HasSubstr("test.yaml:3"), HasSubstr("frontier.costmap.unknown_passable"),
                    HasSubstr("'maybe'")));
  EXPECT_THAT(ErrorOf("frontier:\n  max_segment_m: 2\n"),
              AllOf(HasSubstr("frontier.max_segment_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("frontier:\n  costmap: {inflation_margin_m: 0.4}\n"),
              AllOf(HasSubstr("frontier.costmap.inflation_margin_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("frontier:\n  free_threshold: 70\n"),
              AllOf(HasSubstr("frontier.free_threshold"), HasSubstr("'70'"),
                    HasSubstr("occupied_threshold")));
  EXPECT_THAT(ErrorOf("frontier:\n  max_segment_length_m: 0.4\n"),
              AllOf(HasSubstr("frontier.max_segment_length_m"), HasSubstr("min_size_m")));
  EXPECT_THAT(ErrorOf("frontier:\n  robot_radius_m: 0\n"), HasSubstr("frontier.robot_radius_m"));
}

}  // namespace
}  // namespace aslam
