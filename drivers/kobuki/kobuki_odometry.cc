#include "drivers/kobuki/kobuki_odometry.h"

#include <cmath>

namespace aslam {
namespace {

// Ticks moved between two readings of a 16-bit counter, forward or backward.
int TickDelta(uint16_t from, uint16_t to) { return static_cast<int16_t>(to - from); }

double GyroRad(const kobuki::InertialSensorData& inertial) {
  return inertial.angle_cdeg * 0.01 * M_PI / 180.0;
}

}  // namespace

double KobukiGeometry::MetresPerTick() const {
  return 2.0 * M_PI * wheel_radius_m / ticks_per_revolution;
}

KobukiOdometry::KobukiOdometry(KobukiGeometry geometry, bool gyro_heading)
    : geometry_(geometry), gyro_heading_(gyro_heading) {}

void KobukiOdometry::Restart() { started_ = false; }

std::optional<Odometry> KobukiOdometry::Update(
    int64_t utime, const kobuki::BasicSensorData& basic,
    const std::optional<kobuki::InertialSensorData>& inertial) {
  const bool use_gyro = gyro_heading_ && inertial.has_value();
  if (!started_) {
    started_ = true;
    last_ = basic;
    if (use_gyro) last_gyro_rad_ = GyroRad(*inertial);
    return std::nullopt;
  }
  const double m_per_tick = geometry_.MetresPerTick();
  const double left_m = TickDelta(last_.left_encoder, basic.left_encoder) * m_per_tick;
  const double right_m = TickDelta(last_.right_encoder, basic.right_encoder) * m_per_tick;
  // The base's clock, not the arrival, times the motion: USB latency does not jitter it.
  const int dt_ms = static_cast<uint16_t>(basic.timestamp_ms - last_.timestamp_ms);
  last_ = basic;

  const double distance_m = 0.5 * (left_m + right_m);
  double dyaw_rad = (right_m - left_m) / geometry_.wheel_base_m;
  double yaw_rate_radps = 0.0;
  if (use_gyro) {
    const double gyro_rad = GyroRad(*inertial);
    dyaw_rad = WrapAngle(gyro_rad - last_gyro_rad_);
    last_gyro_rad_ = gyro_rad;
    yaw_rate_radps = inertial->angle_rate_cdeg * 0.01 * M_PI / 180.0;
  }
  // Midpoint heading: exact for an arc at constant curvature to second order.
  const double mid_yaw = pose_.yaw_rad + 0.5 * dyaw_rad;
  pose_.x_m += distance_m * std::cos(mid_yaw);
  pose_.y_m += distance_m * std::sin(mid_yaw);
  pose_.yaw_rad = WrapAngle(pose_.yaw_rad + dyaw_rad);

  Odometry odometry;
  odometry.utime = utime;
  odometry.seq = seq_++;
  odometry.pose = pose_;
  if (dt_ms > 0) {
    odometry.linear_velocity_mps = distance_m / (dt_ms * 1e-3);
    if (!use_gyro) yaw_rate_radps = dyaw_rad / (dt_ms * 1e-3);
  }
  odometry.angular_velocity_radps = yaw_rate_radps;
  return odometry;
}

}  // namespace aslam
