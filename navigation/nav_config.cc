#include "navigation/nav_config.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace aslam {
namespace {

std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void LoadLocalObstacles(const ConfigReader& c, LocalObstaclesOptions* o) {
  c.ReadInRange("window_m", &o->window_m, 1.0, 100.0);
  c.ReadInRange("resolution_m", &o->resolution_m, 0.005, 1.0);
  c.ReadInRange("occupied_threshold", &o->occupied_threshold, 1, 100);
}

void LoadDwa(const ConfigReader& c, DwaOptions* o) {
  c.ReadInRange("min_linear_mps", &o->min_linear_mps, -20.0, 20.0);
  c.ReadInRange("control_period_s", &o->control_period_s, 1e-3, 10.0);
  c.ReadInRange("horizon_s", &o->horizon_s, 0.05, 30.0);
  c.ReadInRange("rollout_step_s", &o->rollout_step_s, 1e-3, 10.0);
  c.ReadInRange("linear_samples", &o->linear_samples, 1, 1000);
  c.ReadInRange("angular_samples", &o->angular_samples, 1, 1000);
  c.ReadInRange("weight_path_alignment", &o->weight_path_alignment, 0.0, 1000.0);
  c.ReadInRange("weight_goal_heading", &o->weight_goal_heading, 0.0, 1000.0);
  c.ReadInRange("weight_clearance", &o->weight_clearance, 0.0, 1000.0);
  c.ReadInRange("weight_speed", &o->weight_speed, 0.0, 1000.0);
  c.ReadInRange("clearance_cap_m", &o->clearance_cap_m, 0.01, 100.0);
  c.ReadInRange("goal_lookahead_m", &o->goal_lookahead_m, 0.01, 100.0);
  c.Read("escape_inside_margin", &o->escape_inside_margin);
  if (o->min_linear_mps > o->max_linear_mps) {
    c.Fail("min_linear_mps", "must not exceed robot.max_linear_mps = " + Number(o->max_linear_mps));
  }
  if (o->rollout_step_s > o->horizon_s) c.Fail("rollout_step_s", "must not exceed horizon_s");
}

void LoadNavigator(const ConfigReader& c, NavigatorOptions* o) {
  c.ReadInRange("goal_tolerance_m", &o->goal_tolerance_m, 0.01, 10.0);
  c.ReadInRange("goal_snap_m", &o->goal_snap_m, 0.0, 10.0);
  c.ReadInRange("replan_period_s", &o->replan_period_s, 0.05, 3600.0);
  c.ReadInRange("path_lookahead_m", &o->path_lookahead_m, 0.1, 100.0);
  c.ReadInRange("scan_mark_range_m", &o->scan_mark_range_m, 0.0, 100.0);
  c.ReadInRange("scan_mark_clear_margin_m", &o->scan_mark_clear_margin_m, 0.01, 10.0);
  c.ReadInRange("detour_factor", &o->detour_factor, 0.0, 1000.0);
  c.ReadInRange("detour_slack_m", &o->detour_slack_m, 0.0, 10000.0);
  c.ReadInRange("align_start_rad", &o->align_start_rad, 0.0, 4.0);
  c.ReadInRange("align_done_rad", &o->align_done_rad, 0.01, M_PI);
  c.ReadInRange("align_speed_radps", &o->align_speed_radps, 0.05, 20.0);
  c.ReadInRange("pose_timeout_s", &o->pose_timeout_s, 0.01, 60.0);
  c.ReadInRange("progress_timeout_s", &o->progress_timeout_s, 0.1, 3600.0);
  c.ReadInRange("progress_margin_m", &o->progress_margin_m, 0.0, 100.0);
  c.ReadInRange("dwa_failures_for_recovery", &o->dwa_failures_for_recovery, 1, 10000);
  c.ReadInRange("max_recoveries", &o->max_recoveries, 0, 1000);
  c.ReadInRange("squeeze_margin_m", &o->squeeze_margin_m, 0.0, 10.0);
  if (o->align_done_rad > o->align_start_rad)
    c.Fail("align_done_rad", "must not exceed align_start_rad");

  const ConfigReader r = c.Section("recovery");
  RecoveryOptions& ro = o->recovery;
  r.ReadInRange("rotate_speed_radps", &ro.rotate_speed_radps, 0.01, 20.0);
  r.ReadInRange("rotate_aligned_rad", &ro.rotate_aligned_rad, 0.001, M_PI);
  r.ReadInRange("back_off_distance_m", &ro.back_off_distance_m, 0.0, 10.0);
  r.ReadInRange("back_off_speed_mps", &ro.back_off_speed_mps, 0.01, 5.0);
  r.ReadInRange("rear_clearance_margin_m", &ro.rear_clearance_margin_m, 0.0, 5.0);
}

// The robot's radius and clearance margin are set before: not keys here.
void LoadCostmap(const ConfigReader& c, CostmapOptions* o) {
  c.ReadInRange("inflation_margin_m", &o->inflation_margin_m, 0.0, 10.0);
  c.ReadInRange("cost_scaling_per_m", &o->cost_scaling_per_m, 0.0, 1000.0);
  c.ReadInRange("occupied_threshold", &o->occupied_threshold, 1, 100);
  c.Read("unknown_passable", &o->unknown_passable);
  c.ReadInRange("unknown_cost", &o->unknown_cost, 0, 252);
}

void LoadGlobalPlanner(const ConfigReader& c, GlobalPlannerOptions* o) {
  c.ReadInRange("cost_weight", &o->cost_weight, 0.0, 1000.0);
  c.ReadInRange("start_escape_m", &o->start_escape_m, 0.0, 5.0);
}

// The components' own checks (cross-field ones included), reported against the section.
template <typename Options>
void Validate(const ConfigReader& nav, const std::string& name, const Options& options) {
  try {
    options.Validate();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(nav.file() + ": section " + name + ": " + e.what());
  }
}

}  // namespace

NavOptions LoadNavOptions(const ConfigReader& nav, const RobotOptions& robot) {
  NavOptions options;
  // One radius and one margin for the costmap's inscribed zone and the DWA's
  // collision circle: the planner never routes through a gap the DWA refuses.
  options.costmap.robot_radius_m = robot.radius_m;
  options.costmap.clearance_margin_m = robot.clearance_margin_m;
  options.dwa.robot_radius_m = robot.radius_m;
  options.dwa.safety_margin_m = robot.clearance_margin_m;
  options.dwa.max_linear_mps = robot.max_linear_mps;
  options.dwa.max_angular_radps = robot.max_angular_radps;
  options.dwa.max_linear_accel_mps2 = robot.max_linear_accel_mps2;
  options.dwa.max_angular_accel_radps2 = robot.max_angular_accel_radps2;

  LoadNavigator(nav, &options.navigator);
  const ConfigReader costmap = nav.Section("costmap");
  LoadCostmap(costmap, &options.costmap);
  const ConfigReader global_planner = nav.Section("global_planner");
  LoadGlobalPlanner(global_planner, &options.global_planner);
  const ConfigReader local_obstacles = nav.Section("local_obstacles");
  LoadLocalObstacles(local_obstacles, &options.local_obstacles);
  const ConfigReader dwa = nav.Section("dwa");
  LoadDwa(dwa, &options.dwa);
  nav.CheckAllKeysUsed();
  Validate(nav, nav.KeyPath("costmap"), options.costmap);
  Validate(nav, nav.KeyPath("global_planner"), options.global_planner);
  Validate(nav, nav.KeyPath("local_obstacles"), options.local_obstacles);
  Validate(nav, nav.KeyPath("dwa"), options.dwa);

  if (options.navigator.squeeze_margin_m > robot.clearance_margin_m) {
    nav.Fail("squeeze_margin_m",
             "must not exceed robot.clearance_margin_m = " + Number(robot.clearance_margin_m));
  }

  // Rollouts leaving the local window read as blocked: the window must hold the longest one.
  const double reach_m = options.dwa.max_linear_mps * options.dwa.horizon_s + robot.radius_m +
                         robot.clearance_margin_m;
  if (reach_m > 0.5 * options.local_obstacles.window_m) {
    local_obstacles.Fail("window_m",
                         "must be at least twice the DWA reach, robot.max_linear_mps * "
                         "dwa.horizon_s + robot.radius_m + robot.clearance_margin_m = " +
                             Number(reach_m) + " m");
  }
  return options;
}

NavOptions LoadNavOptionsFromFile(const std::string& file) {
  const RobotOptions robot = LoadRobotOptionsFromFile(file);
  return LoadNavOptions(ConfigReader::FromOptionalFile(file, "nav"), robot);
}

}  // namespace aslam
