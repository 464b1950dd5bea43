#include "slam/scan_deskew.h"

#include <algorithm>
#include <cmath>

namespace aslam {

LidarScan DeskewScan(const LidarScan& scan, const BaseMotion& base_motion) {
  if (scan.beam_time_s.empty()) return scan;
  LidarScan out = scan;
  out.beam_time_s.clear();
  const int num_beams = static_cast<int>(scan.range_m.size());
  std::fill(out.range_m.begin(), out.range_m.end(), 0.0f);
  const bool full_circle = num_beams * scan.angle_increment_rad >= 2.0 * M_PI - 1e-6;
  const Pose2d& mount = scan.sensor_pose;
  const Pose2d mount_inverse = mount.Inverse();
  for (int i = 0; i < num_beams; ++i) {
    if (!scan.IsValidReturn(i)) continue;
    // The sensor at the beam's time, seen from the sensor at the reference time.
    const Pose2d sensor_motion = mount_inverse * base_motion(scan.beam_time_s[i]) * mount;
    const double angle = scan.BeamAngle(i);
    const double range = scan.range_m[i];
    const Point2d end = sensor_motion.Transform({range * std::cos(angle), range * std::sin(angle)});
    const double deskewed_range = std::hypot(end.x_m, end.y_m);
    if (deskewed_range < scan.range_min_m || deskewed_range > scan.range_max_m) continue;
    // The end point's angle past angle_min, in [0, 2 pi).
    double past_min_rad = std::atan2(end.y_m, end.x_m) - scan.angle_min_rad;
    past_min_rad -= 2.0 * M_PI * std::floor(past_min_rad / (2.0 * M_PI));
    long bin = std::lround(past_min_rad / scan.angle_increment_rad);
    if (full_circle) {
      bin %= num_beams;
    } else if (bin >= num_beams) {
      continue;  // turned out of a partial field of view
    }
    float& stored = out.range_m[bin];
    if (stored == 0.0f || deskewed_range < stored) stored = static_cast<float>(deskewed_range);
  }
  return out;
}

}  // namespace aslam
