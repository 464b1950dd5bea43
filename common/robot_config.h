#pragma once

// The robot, described once: the top-level `robot:` config section, loaded
// and validated once and handed to every component that needs it (the
// simulator's base and lidar, the navigator's costmap and DWA, and through the
// navigator's planning options the frontier extractor and the utility), so
// that no value must be kept equal by hand across sections
// (docs/architecture.md §7).

#include <string>

#include "common/config.h"
#include "common/pose2d.h"

namespace aslam {

struct RobotOptions {
  double radius_m = 0.20;  // the footprint: a disc
  // Inscribed zone = radius + this, for the global planner's costmap and the
  // DWA's collision circle alike: the planner never routes through a gap the
  // DWA refuses to drive through.
  double clearance_margin_m = 0.05;
  double max_linear_mps = 0.5;
  double max_angular_radps = 1.8;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
  Pose2d lidar_mount;  // the lidar in the base frame (LidarScan::sensor_pose)
};

// Reads and validates the `robot` section; throws ConfigError naming file, key and value.
RobotOptions LoadRobotOptions(const ConfigReader& robot_section);
// Convenience: the `robot` section of `file`; "" gives the defaults.
RobotOptions LoadRobotOptionsFromFile(const std::string& file);

}  // namespace aslam
