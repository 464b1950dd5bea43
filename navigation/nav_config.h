#pragma once

// The navigator's options (one struct for the whole aslam-nav component) and
// the loader of the `nav:` config section, validated once at load time. The
// robot's radius, clearance margin and limits come from the `robot:` section
// (common/robot_config.h). Frontier and utility take their costmap, planner
// and goal snap from these options: "reachable" and path lengths are where
// and how the navigator plans.

#include <string>

#include "common/config.h"
#include "common/robot_config.h"
#include "navigation/costmap.h"
#include "navigation/dwa_planner.h"
#include "navigation/global_planner.h"
#include "navigation/local_obstacles.h"

namespace aslam {

struct RecoveryOptions {
  double rotate_speed_radps = 1.0;
  double rotate_aligned_rad = 0.1;  // the turn ends this close to its target heading
  double back_off_distance_m = 0.3;
  double back_off_speed_mps = 0.1;
  double rear_clearance_margin_m = 0.03;  // rear free beyond the robot radius to keep reversing
};

struct NavigatorOptions {
  double goal_tolerance_m = 0.3;
  // A goal the robot cannot stand on or get to (not in an obstacle) is approached at the
  // nearest reachable cell within this distance that sees it; reached is then within
  // goal_tolerance_m of either.
  double goal_snap_m = 0.5;
  double replan_period_s = 1.0;
  double path_lookahead_m = 2.5;  // how much of the global path the DWA follows
  // Scan end points this close to the robot are marked as obstacles in the
  // costmap the global planner uses, so replanning routes around what the map
  // has not caught up with (0 = plan on the map alone). A mark lasts as long as the goal,
  // until the map holds the cell as an obstacle or a later beam returns from more than
  // scan_mark_clear_margin_m beyond it: the plan must not change with the robot's distance.
  double scan_mark_range_m = 3.0;
  double scan_mark_clear_margin_m = 0.15;  // above the lidar's range noise where marks lie
  // Scan marks that shut the planned way fail the goal when the trip (driven + the way round)
  // is longer than detour_factor x the goal's first plan + detour_slack_m (0: never).
  double detour_factor = 3.0;
  double detour_slack_m = 10.0;
  // Heading error to the path beyond align_start_rad: stop and turn in place
  // until within align_done_rad before the DWA drives again (the DWA alone
  // turns around in wide circles when speed scores well).
  double align_start_rad = 1.2;
  double align_done_rad = 0.3;
  double align_speed_radps = 1.5;
  double pose_timeout_s = 0.5;        // an older pose (or scan) stops the robot
  double progress_timeout_s = 10.0;   // no progress this long starts a recovery
  double progress_margin_m = 0.25;    // progress = this much net advance along the paths
  int dwa_failures_for_recovery = 3;  // consecutive cycles without an admissible trajectory
  int max_recoveries = 3;             // per goal; one more need for recovery fails the goal
  // Once a goal has needed a recovery (no progress, no trajectory), the DWA keeps this margin
  // instead of the robot's clearance margin for the rest of the goal: a gap the robot drove
  // into, or the planner routes through, that a newer scan narrows by a cell can be left.
  double squeeze_margin_m = 0.02;
  RecoveryOptions recovery;
};

// The DWA weights the navigator ships with, tuned in closed loop with
// aslam-nav-bench (worlds/test, worlds/office). With DwaOptions' own weights
// (1.0, 0.8, 0.4, 0.3) the min-max normalised clearance term outweighs speed
// near doorways: from a standstill, staying put scores best and the robot
// stalls (aslam-nav-bench, worlds/test, 50 runs: 70 % reached vs 100 % with these).
inline DwaOptions NavDefaultDwaOptions() {
  DwaOptions dwa;
  dwa.weight_path_alignment = 0.5;
  dwa.weight_goal_heading = 0.5;
  dwa.weight_clearance = 0.2;
  dwa.weight_speed = 1.0;
  return dwa;
}

struct NavOptions {
  CostmapOptions costmap;
  GlobalPlannerOptions global_planner;
  LocalObstaclesOptions local_obstacles;
  DwaOptions dwa = NavDefaultDwaOptions();
  NavigatorOptions navigator;
};

// Reads and validates the `nav` section for `robot`; throws ConfigError naming
// file, key and value.
NavOptions LoadNavOptions(const ConfigReader& nav_section, const RobotOptions& robot);
// Convenience: the `robot` and `nav` sections of `file`; "" gives the defaults.
NavOptions LoadNavOptionsFromFile(const std::string& file);

}  // namespace aslam
