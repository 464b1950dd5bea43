#pragma once

// Sensor and command value types shared by the algorithm libraries. The LCM
// translators (`*_lcm.h`) map these to and from the lcmtypes.

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/pose2d.h"

namespace aslam {

// A planar lidar sweep. Beam i points at angle_min_rad + i*angle_increment_rad
// in the sensor frame, measured at utime + beam_time_s[i]; range 0 means no
// return (see lidar_scan_t.lcm).
struct LidarScan {
  int64_t utime = 0;
  int64_t seq = 0;
  Pose2d sensor_pose;  // sensor in the base frame
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> range_m;
  // When each beam was measured, seconds after utime: empty for an instantaneous
  // sweep, else one per beam (a spinning lidar's sweep takes its whole period).
  std::vector<float> beam_time_s;

  double BeamTimeS(std::size_t i) const { return beam_time_s.empty() ? 0.0 : beam_time_s[i]; }

  double BeamAngle(std::size_t i) const { return angle_min_rad + i * angle_increment_rad; }
  bool IsValidReturn(std::size_t i) const {
    const float r = range_m[i];
    // 0 is "no return" even when range_min_m is 0; NaN and inf never count.
    return r > 0.0f && std::isfinite(r) && r >= range_min_m && r <= range_max_m;
  }
};

// Integrated wheel odometry: the base in the "odom" frame.
struct Odometry {
  int64_t utime = 0;
  int64_t seq = 0;
  Pose2d pose;
  double linear_velocity_mps = 0.0;
  double angular_velocity_radps = 0.0;
};

struct VelocityCommand {
  int64_t utime = 0;
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

// A pose at a time, in a named frame.
struct StampedPose {
  int64_t utime = 0;
  Pose2d pose;
  double linear_velocity_mps = 0.0;
  double angular_velocity_radps = 0.0;
};

}  // namespace aslam
