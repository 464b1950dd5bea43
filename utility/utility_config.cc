#include "utility/utility_config.h"

#include <stdexcept>
#include <string>

namespace aslam {
namespace {

void LoadHallucination(const ConfigReader& c, HallucinationOptions* o) {
  c.ReadInRange("path_cells_per_node", &o->path_cells_per_node, 1, 100000);
  c.ReadPositive("odometry_sigma_xx", &o->odometry_sigma_xx);
  c.Read("odometry_sigma_xy", &o->odometry_sigma_xy);
  c.ReadPositive("odometry_sigma_yy", &o->odometry_sigma_yy);
  c.ReadPositive("odometry_sigma_yawyaw", &o->odometry_sigma_yawyaw);
  // Σ_odo must be invertible (positive definite) for I_odo = ½ Σ⁻¹.
  if (o->odometry_sigma_xy * o->odometry_sigma_xy >= o->odometry_sigma_xx * o->odometry_sigma_yy) {
    c.Fail("odometry_sigma_xy", "needs xy^2 < xx * yy (covariance positive definite)");
  }
  c.ReadInRange("unknown_radius_m", &o->unknown_radius_m, 0.0, 100.0);
  c.ReadInRange("loop_closure_radius_m", &o->loop_closure_radius_m, 0.0, 100.0);
  c.ReadInRange("max_loop_closures_per_node", &o->max_loop_closures_per_node, 0, 1000);
  c.ReadInRange("exclude_newest_nodes", &o->exclude_newest_nodes, 0, 1000000);
  c.ReadInRange("occupied_fraction_threshold", &o->occupied_fraction_threshold, 0.0, 1.0);
  c.ReadInRange("loop_closure_scale", &o->loop_closure_scale, 0.0, 1e6);
}

}  // namespace

UtilityOptions LoadUtilityOptions(const ConfigReader& u, const NavOptions& nav) {
  UtilityOptions options;
  GoalSelectorOptions& s = options.selector;
  s.costmap = nav.costmap;
  s.global_planner = nav.global_planner;
  s.goal_snap_m = nav.navigator.goal_snap_m;

  std::string method = UtilityMethodName(s.method);
  u.Read("method", &method);
  const auto parsed = ParseUtilityMethod(method);
  if (!parsed) u.Fail("method", "expected fd, ags or ours");
  s.method = *parsed;

  u.ReadInRange("lambda", &s.path_entropy.lambda, 0.0, 1000.0);
  std::string unit = "m";
  u.Read("distance_unit", &unit);
  if (unit == "m") {
    s.path_entropy.distance_unit = DistanceUnit::kMeters;
  } else if (unit == "cells") {
    s.path_entropy.distance_unit = DistanceUnit::kCells;
  } else {
    u.Fail("distance_unit", "expected m or cells");
  }
  u.ReadInRange("min_distance_m", &s.min_distance_m, 0.0, 100.0);
  u.ReadInRange("blacklist_radius_m", &s.blacklist_radius_m, 0.0, 100.0);
  u.ReadInRange("done_timeout_s", &options.done_timeout_s, 0.0, 1e6);
  u.Read("return_home", &options.return_home);
  u.Read("ours_keeps_vanished_goal", &options.ours_keeps_vanished_goal);
  u.ReadInRange("ours_pocket_max_area_m2", &options.ours_pocket_max_area_m2, 0.0, 1e6);
  u.ReadInRange("ours_pocket_near_m", &options.ours_pocket_near_m, 0.0, 1e6);
  u.ReadInRange("ours_max_path_length_m", &options.ours_max_path_length_m, 0.0, 1e6);
  LoadHallucination(u.Section("hallucination"), &s.hallucination);
  u.CheckAllKeysUsed();

  // The components' own checks (cross-field ones included), reported against the section.
  try {
    s.Validate();
  } catch (const std::invalid_argument& e) {
    std::string section = u.KeyPath("");
    section.pop_back();  // KeyPath("") ends in the separator
    throw ConfigError(u.file() + ": section " + section + ": " + e.what());
  }
  return options;
}

GoalSelectorOptions SelectorOptionsForMethod(const UtilityOptions& options) {
  GoalSelectorOptions selector = options.selector;
  const bool ours = selector.method == UtilityMethod::kOurs;
  selector.pocket_max_area_m2 = ours ? options.ours_pocket_max_area_m2 : 0.0;
  selector.pocket_near_m = ours ? options.ours_pocket_near_m : 0.0;
  selector.max_path_length_m = ours ? options.ours_max_path_length_m : 0.0;
  return selector;
}

ExplorationOptions ExplorationOptionsForMethod(const UtilityOptions& options) {
  const UtilityMethod method = options.selector.method;
  return ExplorationOptions{method, options.done_timeout_s, options.return_home,
                            options.ours_keeps_vanished_goal && method == UtilityMethod::kOurs};
}

UtilityOptions LoadUtilityOptionsFromFile(const std::string& file) {
  const NavOptions nav = LoadNavOptionsFromFile(file);
  return LoadUtilityOptions(ConfigReader::FromOptionalFile(file, "utility"), nav);
}

}  // namespace aslam
