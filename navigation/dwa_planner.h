#pragma once

// The Dynamic Window Approach (Fox, Burgard, Thrun 1997): sample (v, w)
// reachable within one control period under the acceleration limits, roll
// each out at constant velocity over a horizon, discard any whose robot
// circle hits an obstacle, and score the rest on path alignment, goal
// heading, clearance and speed.
//
// Safety: a rollout is checked over the whole horizon (and further if
// braking at full deceleration along the same arc would take longer), at
// sub-steps short enough that the centre moves at most half a cell between
// checks. If every sample collides but braking along the current arc is
// free, the planner brakes (DwaResult::braking). Each score term is min-max
// normalised over the collision-free candidates so the weights compare; goal
// heading is taken where the robot would stop if it braked after this period.

#include <vector>

#include "common/pose2d.h"
#include "navigation/local_obstacles.h"

namespace aslam {

struct DwaOptions {
  double max_linear_mps = 0.5;
  double min_linear_mps = 0.0;  // no reversing in normal driving
  double max_angular_radps = 1.8;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
  double control_period_s = 0.1;  // one command per scan
  double horizon_s = 2.0;
  double rollout_step_s = 0.1;
  int linear_samples = 11;
  int angular_samples = 21;
  double robot_radius_m = 0.20;
  double safety_margin_m = 0.05;  // a rollout closer than radius + margin collides
  double weight_path_alignment = 1.0;
  double weight_goal_heading = 0.8;
  double weight_clearance = 0.4;
  double weight_speed = 0.3;
  double clearance_cap_m = 1.0;  // clearance beyond this scores the same
  // Goal heading aims at the path point this far (along the path) past the
  // point nearest the robot, or the goal if nearer; keep it beyond
  // max_linear_mps * horizon_s so rollouts do not overshoot it.
  double goal_lookahead_m = 1.5;
  // A robot already closer than radius + margin (a new scan point, a pose
  // jump) may still take rollouts that never get closer than it is now
  // (turning in place always qualifies) instead of freezing; false: every
  // rollout collides and Plan reports found = false.
  bool escape_inside_margin = true;

  // Throws std::invalid_argument naming the option and its value.
  void Validate() const;
};

struct DwaVelocity {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

struct DwaResult {
  bool found = false;  // false: every sampled trajectory collides
  // `command` slows v and w together, braking along the current arc, and
  // that is free: every sample collided (the horizon slid onto an obstacle;
  // not stuck, so no reason for recovery) or the path is empty.
  bool braking = false;
  // found: the best command; else the window's velocity nearest (0, 0) (brake).
  DwaVelocity command;
  double score = 0.0;  // weighted normalised cost of the command; lower is better
  int trajectories_evaluated = 0;
  int trajectories_colliding = 0;
  std::vector<Pose2d> best_rollout;  // for viewers and tests; when braking, the braking path
};

class DwaPlanner {
 public:
  // Aborts on invalid options: callers validate config at load time.
  explicit DwaPlanner(DwaOptions options);

  // `path_m`: the global path ("map"), nearest point first or anywhere along
  // it; the planner follows it toward its last point (the goal). An empty
  // path means "no goal": the command brakes along the current arc (found
  // when that is collision-free). `current` is clamped to the velocity
  // limits first.
  DwaResult Plan(const Pose2d& robot_in_map, const DwaVelocity& current,
                 const std::vector<Point2d>& path_m, const LocalObstacles& obstacles) const;

  // The constant-velocity rollout of `velocity` from `start` (public for
  // tests): exact arcs, `start` first, then one pose per rollout_step_s up
  // to horizon_s (the last step may be shorter).
  std::vector<Pose2d> Rollout(const Pose2d& start, const DwaVelocity& velocity) const;

  const DwaOptions& options() const { return options_; }

 private:
  DwaOptions options_;
};

}  // namespace aslam
