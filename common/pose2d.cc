#include "common/pose2d.h"

#include <sstream>

namespace aslam {

double WrapAngle(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI) wrapped += 2.0 * M_PI;
  return wrapped;
}

Pose2d Pose2d::Compose(const Pose2d& other) const {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  return {x_m + c * other.x_m - s * other.y_m, y_m + s * other.x_m + c * other.y_m,
          WrapAngle(yaw_rad + other.yaw_rad)};
}

Pose2d Pose2d::Inverse() const {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  return {-c * x_m - s * y_m, s * x_m - c * y_m, WrapAngle(-yaw_rad)};
}

Pose2d Pose2d::Between(const Pose2d& other) const {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const double dx = other.x_m - x_m, dy = other.y_m - y_m;
  return {c * dx + s * dy, -s * dx + c * dy, WrapAngle(other.yaw_rad - yaw_rad)};
}

Point2d Pose2d::Transform(const Point2d& point) const {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  return {x_m + c * point.x_m - s * point.y_m, y_m + s * point.x_m + c * point.y_m};
}

std::ostream& operator<<(std::ostream& os, const Pose2d& pose) {
  return os << "(" << pose.x_m << " m, " << pose.y_m << " m, " << pose.yaw_rad << " rad)";
}

std::optional<Pose2d> ParsePose(const std::string& text) {
  std::istringstream in(text);
  Pose2d pose;
  char c1 = 0, c2 = 0;
  if (!(in >> pose.x_m >> c1 >> pose.y_m >> c2 >> pose.yaw_rad) || c1 != ',' || c2 != ',' ||
      !(in >> std::ws).eof() || !std::isfinite(pose.x_m) || !std::isfinite(pose.y_m) ||
      !std::isfinite(pose.yaw_rad)) {
    return std::nullopt;
  }
  return pose;
}

Pose2d Interpolate(const Pose2d& a, const Pose2d& b, double fraction) {
  return Pose2d{a.x_m + fraction * (b.x_m - a.x_m), a.y_m + fraction * (b.y_m - a.y_m),
                WrapAngle(a.yaw_rad + fraction * WrapAngle(b.yaw_rad - a.yaw_rad))};
}

}  // namespace aslam
