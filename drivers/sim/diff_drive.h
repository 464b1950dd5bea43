#pragma once

// The simulated differential-drive base: the robot's velocity and
// acceleration limits, exact arc integration and stop-at-contact collision of
// its disc with the world.

#include "common/pose2d.h"
#include "drivers/sim/sim_world.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

// A planar body velocity: forward speed and yaw rate (counter-clockwise positive).
struct Twist2d {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

struct DiffDriveStepResult {
  bool collided = false;  // the step ended at contact and the base stopped
};

class DiffDriveBase {
 public:
  explicit DiffDriveBase(const RobotOptions& options, const Pose2d& pose_in_world = {});

  const RobotOptions& options() const { return options_; }
  const Pose2d& pose() const { return pose_; }  // base in the world frame
  const Twist2d& velocity() const { return velocity_; }

  // Teleports the base (tests, start) and stops it.
  void SetPose(const Pose2d& pose_in_world);
  void Stop() { velocity_ = {}; }

  // One physics step towards `target`. The target is clamped to the velocity
  // limits and the velocity moves towards it within the acceleration limits;
  // the pose then follows the arc of the new (v, w) for dt_s. If the disc of
  // radius_m would hit a solid cell on the way, the base stops at the last
  // collision-free pose found by bisection and both velocities become 0.
  // Turning in place never collides.
  DiffDriveStepResult Step(const Twist2d& target, double dt_s, const SimWorld& world);

  // The pose reached from `start` after moving at constant (v, w) for dt_s.
  static Pose2d IntegrateArc(const Pose2d& start, double linear_mps, double angular_radps,
                             double dt_s);

 private:
  RobotOptions options_;
  Pose2d pose_;
  Twist2d velocity_;
};

}  // namespace aslam
