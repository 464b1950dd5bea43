#pragma once

// SE(2) pose algebra: the one place the project composes, inverts and
// differences planar poses.

#include <cmath>
#include <optional>
#include <ostream>
#include <string>

namespace aslam {

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle_rad);

struct Point2d {
  double x_m = 0.0;
  double y_m = 0.0;
};

struct Pose2d {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  // this ⊕ other: `other` expressed in this pose's frame, mapped to the parent frame.
  Pose2d Compose(const Pose2d& other) const;
  // The pose whose composition with this one is the identity.
  Pose2d Inverse() const;
  // this⁻¹ ⊕ other: `other` expressed in this pose's frame.
  Pose2d Between(const Pose2d& other) const;
  // A point given in this pose's frame, expressed in the parent frame.
  Point2d Transform(const Point2d& point) const;
};

inline Pose2d operator*(const Pose2d& a, const Pose2d& b) { return a.Compose(b); }

// Linear interpolation from `a` (fraction 0) to `b` (1), the yaw the short way round.
Pose2d Interpolate(const Pose2d& a, const Pose2d& b, double fraction);

std::ostream& operator<<(std::ostream& os, const Pose2d& pose);

// "X,Y,YAW" (m, m, rad), as a --start flag takes it -> pose; nullopt if
// malformed or not finite. Whitespace around the numbers is allowed.
std::optional<Pose2d> ParsePose(const std::string& text);

}  // namespace aslam
