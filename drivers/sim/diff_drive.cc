#include "drivers/sim/diff_drive.h"

#include <algorithm>
#include <cmath>

namespace aslam {
namespace {

// ~10 halvings put the contact within a thousandth of a (sub)step of the wall.
constexpr int kBisectionIterations = 10;
// Collision is tested at least every quarter cell along the path, so no wall is skipped.
constexpr double kMaxCheckSpacingCells = 0.25;

double MoveTowards(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace

DiffDriveBase::DiffDriveBase(const RobotOptions& options, const Pose2d& pose_in_world)
    : options_(options), pose_(pose_in_world) {}

void DiffDriveBase::SetPose(const Pose2d& pose_in_world) {
  pose_ = pose_in_world;
  Stop();
}

Pose2d DiffDriveBase::IntegrateArc(const Pose2d& start, double linear_mps, double angular_radps,
                                   double dt_s) {
  const double distance_m = linear_mps * dt_s;
  const double turn_rad = angular_radps * dt_s;
  Pose2d delta{distance_m, 0.0, turn_rad};
  if (std::abs(turn_rad) > 1e-6) {
    delta.x_m = distance_m * std::sin(turn_rad) / turn_rad;
    delta.y_m = distance_m * (1.0 - std::cos(turn_rad)) / turn_rad;
  } else {
    // Series of the above: 1 - cos loses all digits for tiny angles.
    delta.x_m = distance_m * (1.0 - turn_rad * turn_rad / 6.0);
    delta.y_m = distance_m * turn_rad / 2.0;
  }
  return start.Compose(delta);
}

DiffDriveStepResult DiffDriveBase::Step(const Twist2d& target, double dt_s, const SimWorld& world) {
  const double target_v =
      std::clamp(target.linear_mps, -options_.max_linear_mps, options_.max_linear_mps);
  const double target_w =
      std::clamp(target.angular_radps, -options_.max_angular_radps, options_.max_angular_radps);
  velocity_.linear_mps =
      MoveTowards(velocity_.linear_mps, target_v, options_.max_linear_accel_mps2 * dt_s);
  velocity_.angular_radps =
      MoveTowards(velocity_.angular_radps, target_w, options_.max_angular_accel_radps2 * dt_s);
  const double v = velocity_.linear_mps, w = velocity_.angular_radps;

  const Pose2d start = pose_;
  if (v == 0.0) {
    pose_ = IntegrateArc(start, 0.0, w, dt_s);
    return {};
  }
  auto collides_at = [&](double fraction) {
    const Pose2d p = IntegrateArc(start, v, w, fraction * dt_s);
    return world.CircleCollides({p.x_m, p.y_m}, options_.radius_m);
  };
  const auto stop_at = [&](double fraction) {
    pose_ = IntegrateArc(start, v, w, fraction * dt_s);
    Stop();
    return DiffDriveStepResult{true};
  };

  if (world.CircleCollides({start.x_m, start.y_m}, options_.radius_m)) {
    // Already overlapping (placed there): only a move that ends free is allowed.
    if (collides_at(1.0)) return stop_at(0.0);
    pose_ = IntegrateArc(start, v, w, dt_s);
    return {};
  }
  const double path_cells = std::abs(v * dt_s) / world.resolution_m();
  const int checks = std::max(1, static_cast<int>(std::ceil(path_cells / kMaxCheckSpacingCells)));
  for (int k = 1; k <= checks; ++k) {
    if (!collides_at(static_cast<double>(k) / checks)) continue;
    double free_fraction = static_cast<double>(k - 1) / checks;
    double hit_fraction = static_cast<double>(k) / checks;
    for (int i = 0; i < kBisectionIterations; ++i) {
      const double mid = 0.5 * (free_fraction + hit_fraction);
      (collides_at(mid) ? hit_fraction : free_fraction) = mid;
    }
    return stop_at(free_fraction);
  }
  pose_ = IntegrateArc(start, v, w, dt_s);
  return {};
}

}  // namespace aslam
