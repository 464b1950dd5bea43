#pragma once

// The Dynamic Window Approach (Fox, Burgard, Thrun 1997): sample (v, w)
// reachable within one control period under the acceleration limits, roll
// each out at constant velocity over a horizon, discard any whose robot
// circle hits an obstacle, and score the rest on path alignment, goal
// heading, clearance and speed.

#include <vector>

#include "common/pose2d.h"
#include "navigation/local_obstacles.h"

namespace aslam {

struct DwaOptions {
  double max_linear_mps = 0.5;
  double min_linear_mps = 0.0;        // no reversing in normal driving
  double max_angular_radps = 1.8;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
  double control_period_s = 0.1;      // one command per scan
  double horizon_s = 2.0;
  double rollout_step_s = 0.1;
  int linear_samples = 11;
  int angular_samples = 21;
  double robot_radius_m = 0.20;
  double safety_margin_m = 0.05;      // a rollout closer than radius + margin collides
  double weight_path_alignment = 1.0;
  double weight_goal_heading = 0.8;
  double weight_clearance = 0.4;
  double weight_speed = 0.3;
  double clearance_cap_m = 1.0;       // clearance beyond this scores the same
};


struct DwaVelocity {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

struct DwaResult {
  bool found = false;               // false: every sampled trajectory collides
  DwaVelocity command;
  double score = 0.0;
  int trajectories_evaluated = 0;
  int trajectories_colliding = 0;
  std::vector<Pose2d> best_rollout; // for viewers and tests
};

class DwaPlanner {
 public:
  explicit DwaPlanner(DwaOptions options);

  // `path_m`: the global path ("map"), nearest point first or anywhere along
  // it; the planner follows it toward its last point (the goal).
  DwaResult Plan(const Pose2d& robot_in_map, const DwaVelocity& current,
                 const std::vector<Point2d>& path_m, const LocalObstacles& obstacles) const;

  // The constant-velocity rollout of `velocity` from `start` (public for tests).
  std::vector<Pose2d> Rollout(const Pose2d& start, const DwaVelocity& velocity) const;

  const DwaOptions& options() const { return options_; }

 private:
  DwaOptions options_;
};

}  // namespace aslam
