#include "utility/utility_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "common/config_testing.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kShippedConfig = ShippedConfigPath();

UtilityOptions Load(const std::string& yaml) {
  return LoadUtilityOptions(ConfigReader::FromString(yaml, "utility"), NavOptions{});
}

std::string ErrorOf(const std::string& yaml) {
  return ConfigErrorOf([](const ConfigReader& c) { return LoadUtilityOptions(c, NavOptions{}); },
                       yaml, "utility");
}

TEST(UtilityConfig, ShippedConfigLoadsAndHoldsTheDefaults) {
  const UtilityOptions shipped = LoadUtilityOptionsFromFile(kShippedConfig);
  const UtilityOptions defaults;
  const GoalSelectorOptions& s = shipped.selector;
  const GoalSelectorOptions& d = defaults.selector;
  EXPECT_EQ(s.method, UtilityMethod::kOurs);
  EXPECT_EQ(s.method, d.method);
  EXPECT_DOUBLE_EQ(s.path_entropy.lambda, 0.6);  // paper eq. 6
  EXPECT_EQ(s.path_entropy.distance_unit, DistanceUnit::kMeters);
  EXPECT_DOUBLE_EQ(s.path_entropy.p_unknown, d.path_entropy.p_unknown);
  EXPECT_DOUBLE_EQ(s.path_entropy.p_known, d.path_entropy.p_known);
  EXPECT_DOUBLE_EQ(s.min_distance_m, 0.25);  // docs/architecture.md §5
  EXPECT_EQ(s.max_path_length_m, 0.0);       // the method's selector gets ours_max_path_length_m
  EXPECT_DOUBLE_EQ(s.blacklist_radius_m, d.blacklist_radius_m);
  EXPECT_DOUBLE_EQ(s.goal_snap_m, d.goal_snap_m);
  EXPECT_DOUBLE_EQ(shipped.done_timeout_s, defaults.done_timeout_s);
  EXPECT_TRUE(shipped.ours_keeps_vanished_goal);
  EXPECT_EQ(shipped.ours_keeps_vanished_goal, defaults.ours_keeps_vanished_goal);
  EXPECT_DOUBLE_EQ(shipped.ours_pocket_max_area_m2, defaults.ours_pocket_max_area_m2);
  EXPECT_GT(shipped.ours_pocket_max_area_m2, 0.0);
  EXPECT_DOUBLE_EQ(shipped.ours_pocket_near_m, defaults.ours_pocket_near_m);
  EXPECT_EQ(s.pocket_near_m, 0.0);
  EXPECT_DOUBLE_EQ(shipped.ours_max_path_length_m, defaults.ours_max_path_length_m);
  EXPECT_GT(shipped.ours_max_path_length_m, 0.0);
  EXPECT_EQ(s.pocket_max_area_m2, 0.0);  // the method's selector gets it (below)
  EXPECT_DOUBLE_EQ(s.costmap.robot_radius_m, d.costmap.robot_radius_m);
  EXPECT_DOUBLE_EQ(s.costmap.inflation_margin_m, d.costmap.inflation_margin_m);
  EXPECT_DOUBLE_EQ(s.costmap.cost_scaling_per_m, d.costmap.cost_scaling_per_m);
  EXPECT_EQ(s.costmap.occupied_threshold, d.costmap.occupied_threshold);
  EXPECT_EQ(s.costmap.unknown_passable, d.costmap.unknown_passable);
  EXPECT_EQ(s.costmap.unknown_cost, d.costmap.unknown_cost);
  EXPECT_DOUBLE_EQ(s.global_planner.cost_weight, d.global_planner.cost_weight);
  EXPECT_DOUBLE_EQ(s.global_planner.start_escape_m, d.global_planner.start_escape_m);
  const HallucinationOptions& h = s.hallucination;
  const HallucinationOptions& hd = d.hallucination;
  EXPECT_EQ(h.path_cells_per_node, 100);
  EXPECT_EQ(h.path_cells_per_node, hd.path_cells_per_node);
  EXPECT_DOUBLE_EQ(h.odometry_sigma_xx, hd.odometry_sigma_xx);
  EXPECT_DOUBLE_EQ(h.odometry_sigma_xy, hd.odometry_sigma_xy);
  EXPECT_DOUBLE_EQ(h.odometry_sigma_yy, hd.odometry_sigma_yy);
  EXPECT_DOUBLE_EQ(h.odometry_sigma_yawyaw, hd.odometry_sigma_yawyaw);
  EXPECT_DOUBLE_EQ(h.unknown_radius_m, hd.unknown_radius_m);
  EXPECT_DOUBLE_EQ(h.loop_closure_radius_m, hd.loop_closure_radius_m);
  EXPECT_EQ(h.max_loop_closures_per_node, hd.max_loop_closures_per_node);
  EXPECT_EQ(h.exclude_newest_nodes, hd.exclude_newest_nodes);
  EXPECT_DOUBLE_EQ(h.occupied_fraction_threshold, hd.occupied_fraction_threshold);
  EXPECT_DOUBLE_EQ(h.loop_closure_scale, hd.loop_closure_scale);
}

// Path lengths and reachability must be the ones the navigator will see:
// the robot and nav sections reach the utility's planning costmap and planner.
TEST(UtilityConfig, PlansAsTheNavigatorPlans) {
  const std::string file = WriteTestConfig(
      "utility_nav.yaml",
      "robot: {radius_m: 0.3, clearance_margin_m: 0.02}\n"
      "nav:\n  goal_tolerance_m: 0.5\n  goal_snap_m: 0.25\n"
      "  costmap: {inflation_margin_m: 0.5, cost_scaling_per_m: 4.0, occupied_threshold: 70,\n"
      "            unknown_passable: false, unknown_cost: 40}\n"
      "  global_planner: {cost_weight: 2.0, start_escape_m: 0.4}\n"
      "utility: {method: fd}\n");
  const UtilityOptions utility = LoadUtilityOptionsFromFile(file);
  const GoalSelectorOptions& s = utility.selector;
  EXPECT_EQ(s.method, UtilityMethod::kFd);
  EXPECT_DOUBLE_EQ(s.costmap.robot_radius_m, 0.3);
  EXPECT_DOUBLE_EQ(s.costmap.clearance_margin_m, 0.02);
  EXPECT_DOUBLE_EQ(s.costmap.inflation_margin_m, 0.5);
  EXPECT_DOUBLE_EQ(s.costmap.cost_scaling_per_m, 4.0);
  EXPECT_EQ(s.costmap.occupied_threshold, 70);
  EXPECT_FALSE(s.costmap.unknown_passable);
  EXPECT_EQ(s.costmap.unknown_cost, 40);
  EXPECT_DOUBLE_EQ(s.global_planner.cost_weight, 2.0);
  EXPECT_DOUBLE_EQ(s.global_planner.start_escape_m, 0.4);
  EXPECT_DOUBLE_EQ(s.goal_snap_m, 0.25);
}

TEST(UtilityConfig, BadRobotOrNavKeysNameFileKeyAndValue) {
  const std::string robot =
      WriteTestConfig("utility_bad_robot.yaml", "robot:\n  clearance_margin_m: wide\n");
  EXPECT_THAT(ConfigErrorOf([&] { LoadUtilityOptionsFromFile(robot); }),
              AllOf(HasSubstr("utility_bad_robot.yaml:2"), HasSubstr("robot.clearance_margin_m"),
                    HasSubstr("'wide'")));
  const std::string nav =
      WriteTestConfig("utility_bad_nav.yaml", "nav:\n  costmap: {unknown_cost: 300}\n");
  EXPECT_THAT(ConfigErrorOf([&] { LoadUtilityOptionsFromFile(nav); }),
              AllOf(HasSubstr("utility_bad_nav.yaml:2"), HasSubstr("nav.costmap.unknown_cost"),
                    HasSubstr("'300'")));
}

TEST(UtilityConfig, EmptyFileNameGivesDefaults) {
  EXPECT_EQ(LoadUtilityOptionsFromFile("").selector.method, UtilityMethod::kOurs);
}

TEST(UtilityConfig, ReadsEveryMethodAndTheCellUnit) {
  const UtilityOptions fd = Load(
      "utility:\n  method: fd\n  blacklist_radius_m: 1.0\n  done_timeout_s: 3\n"
      "  ours_keeps_vanished_goal: false\n");
  EXPECT_EQ(fd.selector.method, UtilityMethod::kFd);
  EXPECT_DOUBLE_EQ(fd.selector.blacklist_radius_m, 1.0);
  EXPECT_DOUBLE_EQ(fd.done_timeout_s, 3.0);
  EXPECT_FALSE(fd.ours_keeps_vanished_goal);
  EXPECT_EQ(SelectorOptionsForMethod(fd).pocket_max_area_m2, 0.0);
  const UtilityOptions ags = Load(
      "utility:\n  method: ags\n  distance_unit: cells\n"
      "  hallucination: {exclude_newest_nodes: 5}\n");
  EXPECT_EQ(ags.selector.method, UtilityMethod::kAgs);
  EXPECT_EQ(ags.selector.path_entropy.distance_unit, DistanceUnit::kCells);
  EXPECT_EQ(ags.selector.hallucination.exclude_newest_nodes, 5);
}

TEST(UtilityConfig, OnlyOursDefersPocketsAndLengthyPaths) {
  const std::string pocket_keys =
      "\n  ours_pocket_max_area_m2: 2.5\n  ours_pocket_near_m: 1.5\n  ours_max_path_length_m: 12\n";
  const UtilityOptions ours = Load("utility:\n  method: ours" + pocket_keys);
  EXPECT_DOUBLE_EQ(ours.ours_pocket_max_area_m2, 2.5);
  EXPECT_DOUBLE_EQ(SelectorOptionsForMethod(ours).pocket_max_area_m2, 2.5);
  EXPECT_DOUBLE_EQ(ours.ours_pocket_near_m, 1.5);
  EXPECT_DOUBLE_EQ(SelectorOptionsForMethod(ours).pocket_near_m, 1.5);
  EXPECT_DOUBLE_EQ(ours.ours_max_path_length_m, 12.0);
  EXPECT_DOUBLE_EQ(SelectorOptionsForMethod(ours).max_path_length_m, 12.0);
  for (const char* other : {"fd", "ags"}) {
    const UtilityOptions o = Load(std::string("utility:\n  method: ") + other + pocket_keys);
    EXPECT_EQ(SelectorOptionsForMethod(o).pocket_max_area_m2, 0.0) << other;
    EXPECT_EQ(SelectorOptionsForMethod(o).pocket_near_m, 0.0) << other;
    EXPECT_EQ(SelectorOptionsForMethod(o).max_path_length_m, 0.0) << other;
  }
  EXPECT_THAT(ErrorOf("utility:\n  ours_pocket_max_area_m2: -1\n"),
              AllOf(HasSubstr("utility.ours_pocket_max_area_m2"), HasSubstr("'-1'")));
  EXPECT_THAT(ErrorOf("utility:\n  ours_pocket_near_m: -3\n"),
              AllOf(HasSubstr("utility.ours_pocket_near_m"), HasSubstr("'-3'")));
  EXPECT_THAT(ErrorOf("utility:\n  ours_max_path_length_m: -2\n"),
              AllOf(HasSubstr("utility.ours_max_path_length_m"), HasSubstr("'-2'")));
  // The old key, which applied to every method, is gone: a config still using it is told so.
  EXPECT_THAT(ErrorOf("utility:\n  max_path_length_m: 15\n"),
              HasSubstr("utility.max_path_length_m"));
}

TEST(UtilityConfig, BadValuesNameFileKeyAndValue) {
  EXPECT_THAT(ErrorOf("utility:\n  method: best\n"),
              AllOf(HasSubstr("test.yaml:2"), HasSubstr("utility.method"), HasSubstr("'best'"),
                    HasSubstr("fd, ags or ours")));
  EXPECT_THAT(ErrorOf("utility:\n  distance_unit: feet\n"),
              AllOf(HasSubstr("utility.distance_unit"), HasSubstr("'feet'")));
  EXPECT_THAT(ErrorOf("utility:\n  lambda: -0.6\n"),
              AllOf(HasSubstr("test.yaml:2"), HasSubstr("utility.lambda"), HasSubstr("'-0.6'")));
  EXPECT_THAT(ErrorOf("utility:\n  blacklist_radius_m: wide\n"),
              AllOf(HasSubstr("utility.blacklist_radius_m"), HasSubstr("'wide'")));
  EXPECT_THAT(ErrorOf("utility:\n  done_timeout_s: -1\n"), HasSubstr("utility.done_timeout_s"));
  EXPECT_THAT(ErrorOf("utility:\n  hallucination:\n    path_cells_per_node: 0\n"),
              AllOf(HasSubstr("test.yaml:3"),
                    HasSubstr("utility.hallucination.path_cells_per_node"), HasSubstr("'0'")));
  EXPECT_THAT(
      ErrorOf("utility:\n  hallucination: {odometry_sigma_xy: 0.05}\n"),
      AllOf(HasSubstr("utility.hallucination.odometry_sigma_xy"), HasSubstr("positive definite")));
  // The planning keys are nav's and the robot's: here they are typos.
  EXPECT_THAT(ErrorOf("utility:\n  costmap: {unknown_cost: 50}\n"),
              AllOf(HasSubstr("utility.costmap"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("utility:\n  goal_snap_m: 0.15\n"),
              AllOf(HasSubstr("utility.goal_snap_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("utility:\n  robot_radius_m: 0.2\n"),
              AllOf(HasSubstr("utility.robot_radius_m"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("utility:\n  lamda: 0.6\n"),
              AllOf(HasSubstr("utility.lamda"), HasSubstr("unknown key")));
  EXPECT_THAT(ErrorOf("utility:\n  hallucination: {sigma: 1}\n"),
              AllOf(HasSubstr("utility.hallucination.sigma"), HasSubstr("unknown key")));
}

}  // namespace
}  // namespace aslam
