#pragma once

// Wheel odometry of a Kobuki from its feedback: encoder ticks (16 bits, wrapping) for the
// distance, the factory-calibrated gyro (or the encoders) for the heading, the base's own
// millisecond clock for the velocities. No I/O here.

#include <cstdint>
#include <optional>

#include "common/sensor_types.h"
#include "drivers/kobuki/kobuki_protocol.h"

namespace aslam {

// The Kobuki's geometry, from its specification.
struct KobukiGeometry {
  double wheel_radius_m = 0.035;
  double wheel_base_m = 0.230;
  double ticks_per_revolution = 2578.33;
  double MetresPerTick() const;
};

class KobukiOdometry {
 public:
  // gyro_heading: the heading from the gyro (drifts far less than the wheels when turning on
  // carpet); else from the encoders' difference.
  KobukiOdometry(KobukiGeometry geometry, bool gyro_heading);

  // One feedback packet, stamped `utime` (host clock). The first only sets the origin;
  // returns the odometry (pose in "odom", from the identity) from the second on.
  std::optional<Odometry> Update(int64_t utime, const kobuki::BasicSensorData& basic,
                                 const std::optional<kobuki::InertialSensorData>& inertial);
  // Forgets the counters (a reconnect: the base may have been power-cycled) but keeps the
  // pose, so "odom" does not jump.
  void Restart();

 private:
  KobukiGeometry geometry_;
  bool gyro_heading_;
  bool started_ = false;
  kobuki::BasicSensorData last_;
  double last_gyro_rad_ = 0.0;
  Pose2d pose_;
  int64_t seq_ = 0;
};

}  // namespace aslam
