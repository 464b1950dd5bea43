#include "navigation/dwa_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace aslam {
namespace {

// Velocities closer than this are the same sample.
constexpr double kSameVelocity = 1e-9;
// A path vertex this much farther than the nearest one still counts as
// nearest, so the earliest pass wins where a path comes back near itself.
constexpr double kNearestVertexSlack_m = 0.1;
// Score terms spread less than this over the candidates carry no preference.
constexpr double kFlatTerm = 1e-9;

template <typename T>
[[noreturn]] void ThrowBadOption(const std::string& name, T value, const std::string& why) {
  std::ostringstream message;
  message << "DwaOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

void RequirePositive(const std::string& name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    ThrowBadOption(name, value, "must be finite and > 0");
}

void RequireNonNegative(const std::string& name, double value) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    ThrowBadOption(name, value, "must be finite and >= 0");
  }
}

// Advances a pose along the exact arc of constant (v, w) by a fixed dt per
// call: composing the same body-frame arc increment keeps every pose on the
// arc, and rotating (cos, sin) avoids trig per step.
class ArcStepper {
 public:
  ArcStepper(const Pose2d& start, double linear_mps, double angular_radps, double dt_s)
      : x_(start.x_m),
        y_(start.y_m),
        yaw_(start.yaw_rad),
        cos_(std::cos(start.yaw_rad)),
        sin_(std::sin(start.yaw_rad)) {
    const double distance_m = linear_mps * dt_s;
    turn_rad_ = angular_radps * dt_s;
    if (std::abs(turn_rad_) > 1e-6) {
      dx_ = distance_m * std::sin(turn_rad_) / turn_rad_;
      dy_ = distance_m * (1.0 - std::cos(turn_rad_)) / turn_rad_;
    } else {
      // Series of the above: 1 - cos loses all digits for tiny angles.
      dx_ = distance_m * (1.0 - turn_rad_ * turn_rad_ / 6.0);
      dy_ = distance_m * turn_rad_ / 2.0;
    }
    turn_cos_ = std::cos(turn_rad_);
    turn_sin_ = std::sin(turn_rad_);
  }

  void Step() {
    x_ += cos_ * dx_ - sin_ * dy_;
    y_ += sin_ * dx_ + cos_ * dy_;
    const double c = cos_ * turn_cos_ - sin_ * turn_sin_;
    sin_ = sin_ * turn_cos_ + cos_ * turn_sin_;
    cos_ = c;
    yaw_ += turn_rad_;
  }

  Point2d position() const { return {x_, y_}; }
  Pose2d pose() const { return {x_, y_, WrapAngle(yaw_)}; }

 private:
  double x_, y_, yaw_, cos_, sin_;
  double dx_ = 0.0, dy_ = 0.0, turn_rad_ = 0.0, turn_cos_ = 1.0, turn_sin_ = 0.0;
};

// The exact pose after moving at constant (v, w) for t_s.
Pose2d ArcPose(const Pose2d& start, double linear_mps, double angular_radps, double t_s) {
  ArcStepper stepper(start, linear_mps, angular_radps, t_s);
  stepper.Step();
  return stepper.pose();
}

double Distance(const Point2d& a, const Point2d& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}

double SquaredDistanceToSegment(const Point2d& p, const Point2d& a, const Point2d& b) {
  const double abx = b.x_m - a.x_m, aby = b.y_m - a.y_m;
  const double length2 = abx * abx + aby * aby;
  double t = 0.0;
  if (length2 > 0.0) {
    t = std::clamp(((p.x_m - a.x_m) * abx + (p.y_m - a.y_m) * aby) / length2, 0.0, 1.0);
  }
  const double dx = p.x_m - (a.x_m + t * abx), dy = p.y_m - (a.y_m + t * aby);
  return dx * dx + dy * dy;
}

double DistanceToPolyline(const Point2d& p, const std::vector<Point2d>& polyline) {
  if (polyline.size() == 1) return Distance(p, polyline.front());
  // One square root for the nearest segment rather than one per segment.
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < polyline.size(); ++i) {
    best = std::min(best, SquaredDistanceToSegment(p, polyline[i], polyline[i + 1]));
  }
  return std::sqrt(best);
}

// `count` values evenly over [lo, hi] plus `extra` when it lies inside.
std::vector<double> Samples(double lo, double hi, int count, double single, double extra) {
  std::vector<double> values;
  if (count == 1 || hi - lo < kSameVelocity) {
    values.push_back(std::clamp(single, lo, hi));
  } else {
    for (int i = 0; i < count; ++i) {
      // Exact end points: hitting the limits exactly matters (v = 0, w = ±max).
      values.push_back(i == count - 1 ? hi : lo + (hi - lo) * i / (count - 1));
    }
  }
  if (extra >= lo && extra <= hi) values.push_back(extra);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end(),
                           [](double a, double b) { return b - a < kSameVelocity; }),
               values.end());
  // unique keeps the first of a run; make sure an exact `extra` survives.
  for (double& value : values) {
    if (std::abs(value - extra) < kSameVelocity) value = extra;
  }
  return values;
}

// The part of the path the local planner looks at.
struct LocalPath {
  std::vector<Point2d> points;  // from the vertex nearest the robot onward
  Point2d lookahead;            // goal-heading target
};

LocalPath MakeLocalPath(const Point2d& robot, const std::vector<Point2d>& path, double lookahead_m,
                        double keep_m) {
  double nearest_m = std::numeric_limits<double>::infinity();
  for (const Point2d& point : path) nearest_m = std::min(nearest_m, Distance(robot, point));
  std::size_t first = 0;
  while (Distance(robot, path[first]) > nearest_m + kNearestVertexSlack_m) ++first;

  LocalPath local;
  local.points.push_back(path[first]);
  local.lookahead = path.back();
  bool lookahead_set = false;
  double along_m = 0.0;
  for (std::size_t i = first + 1; i < path.size(); ++i) {
    const double step_m = Distance(path[i - 1], path[i]);
    if (!lookahead_set && along_m + step_m >= lookahead_m) {
      const double t = step_m > 0.0 ? (lookahead_m - along_m) / step_m : 1.0;
      local.lookahead = {path[i - 1].x_m + t * (path[i].x_m - path[i - 1].x_m),
                         path[i - 1].y_m + t * (path[i].y_m - path[i - 1].y_m)};
      lookahead_set = true;
    }
    along_m += step_m;
    local.points.push_back(path[i]);
    if (along_m >= keep_m && lookahead_set) break;
  }
  return local;
}

}  // namespace

void DwaOptions::Validate() const {
  RequirePositive("max_linear_mps", max_linear_mps);
  if (!std::isfinite(min_linear_mps) || min_linear_mps > max_linear_mps ||
      min_linear_mps < -max_linear_mps) {
    ThrowBadOption("min_linear_mps", min_linear_mps,
                   "must be in [-max_linear_mps, max_linear_mps]");
  }
  RequirePositive("max_angular_radps", max_angular_radps);
  RequirePositive("max_linear_accel_mps2", max_linear_accel_mps2);
  RequirePositive("max_angular_accel_radps2", max_angular_accel_radps2);
  RequirePositive("control_period_s", control_period_s);
  RequirePositive("horizon_s", horizon_s);
  RequirePositive("rollout_step_s", rollout_step_s);
  if (rollout_step_s > horizon_s)
    ThrowBadOption("rollout_step_s", rollout_step_s, "must be <= horizon_s");
  if (horizon_s / rollout_step_s > 10000.0) {
    ThrowBadOption("rollout_step_s", rollout_step_s, "gives more than 10000 steps per horizon");
  }
  if (linear_samples < 1 || linear_samples > 1000) {
    ThrowBadOption("linear_samples", linear_samples, "must be in 1..1000");
  }
  if (angular_samples < 1 || angular_samples > 1000) {
    ThrowBadOption("angular_samples", angular_samples, "must be in 1..1000");
  }
  RequireNonNegative("robot_radius_m", robot_radius_m);
  RequireNonNegative("safety_margin_m", safety_margin_m);
  RequireNonNegative("weight_path_alignment", weight_path_alignment);
  RequireNonNegative("weight_goal_heading", weight_goal_heading);
  RequireNonNegative("weight_clearance", weight_clearance);
  RequireNonNegative("weight_speed", weight_speed);
  RequirePositive("clearance_cap_m", clearance_cap_m);
  RequirePositive("goal_lookahead_m", goal_lookahead_m);
}

DwaPlanner::DwaPlanner(DwaOptions options) : options_(options) {
  try {
    options_.Validate();
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "DwaPlanner: %s\n", error.what());
    std::abort();
  }
}

std::vector<Pose2d> DwaPlanner::Rollout(const Pose2d& start, const DwaVelocity& velocity) const {
  const double step_s = options_.rollout_step_s;
  const int full_steps = static_cast<int>(std::floor(options_.horizon_s / step_s + 1e-9));
  const double rest_s = options_.horizon_s - full_steps * step_s;
  std::vector<Pose2d> poses;
  poses.reserve(full_steps + 2);
  poses.push_back(start);
  ArcStepper stepper(start, velocity.linear_mps, velocity.angular_radps, step_s);
  for (int i = 0; i < full_steps; ++i) {
    stepper.Step();
    poses.push_back(stepper.pose());
  }
  if (rest_s > 1e-9 * step_s) {
    poses.push_back(ArcPose(stepper.pose(), velocity.linear_mps, velocity.angular_radps, rest_s));
  }
  return poses;
}

DwaResult DwaPlanner::Plan(const Pose2d& robot_in_map, const DwaVelocity& current,
                           const std::vector<Point2d>& path_m,
                           const LocalObstacles& obstacles) const {
  const DwaOptions& o = options_;
  // The dynamic window: what one control period of acceleration reaches.
  const double v0 = std::clamp(current.linear_mps, o.min_linear_mps, o.max_linear_mps);
  const double w0 = std::clamp(current.angular_radps, -o.max_angular_radps, o.max_angular_radps);
  const double v_lo = std::max(o.min_linear_mps, v0 - o.max_linear_accel_mps2 * o.control_period_s);
  const double v_hi = std::min(o.max_linear_mps, v0 + o.max_linear_accel_mps2 * o.control_period_s);
  const double w_lo =
      std::max(-o.max_angular_radps, w0 - o.max_angular_accel_radps2 * o.control_period_s);
  const double w_hi =
      std::min(o.max_angular_radps, w0 + o.max_angular_accel_radps2 * o.control_period_s);
  const DwaVelocity brake{std::clamp(0.0, v_lo, v_hi), std::clamp(0.0, w_lo, w_hi)};

  const Point2d start{robot_in_map.x_m, robot_in_map.y_m};
  const double start_clearance_m = obstacles.ClearanceM(start);
  const double required_m = o.robot_radius_m + o.safety_margin_m;
  const double threshold_m =
      o.escape_inside_margin && start_clearance_m < required_m ? start_clearance_m : required_m;
  // At most half a cell of travel between clearance checks.
  const double check_spacing_m = 0.5 * (obstacles.empty() ? 0.05 : obstacles.resolution_m());

  // Time to stop from (v, w) with both ramped down together (the arc kept) at the accel limits.
  auto braking_s = [&](double v, double w) {
    return std::max(std::abs(v) / o.max_linear_accel_mps2,
                    std::abs(w) / o.max_angular_accel_radps2);
  };

  // Min clearance along the rollout, NaN when it collides. Checked past the
  // horizon if braking along the same arc after this period would need longer.
  auto rollout_clearance = [&](double v, double w) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!(start_clearance_m >= threshold_m) || start_clearance_m <= 0.0) return nan;
    if (std::abs(v) < kSameVelocity) return start_clearance_m;  // the centre stays put
    const double check_s = std::max(o.horizon_s, o.control_period_s + 0.5 * braking_s(v, w));
    const double dt_max_s = std::min(o.rollout_step_s, check_spacing_m / std::abs(v));
    const int steps = static_cast<int>(std::ceil(check_s / dt_max_s - 1e-9));
    ArcStepper stepper(robot_in_map, v, w, check_s / steps);
    double min_clearance_m = start_clearance_m;
    for (int i = 0; i < steps; ++i) {
      stepper.Step();
      const double clearance_m = obstacles.ClearanceM(stepper.position());
      if (clearance_m < threshold_m || clearance_m <= 0.0) return nan;
      min_clearance_m = std::min(min_clearance_m, clearance_m);
    }
    return min_clearance_m;
  };

  // Slows v and w together (at the accel limits), which keeps the current
  // arc: found when the robot stops on it, within what (v0, w0) covers in
  // half the stopping time, without colliding; else the window's velocity
  // nearest (0, 0).
  auto BrakeAlongArc = [&](DwaResult* out) {
    const double stop_s = braking_s(v0, w0);
    const double keep = stop_s > o.control_period_s ? 1.0 - o.control_period_s / stop_s : 0.0;
    const DwaVelocity along_arc{v0 * keep, w0 * keep};
    std::vector<Pose2d> poses{robot_in_map};
    bool free = along_arc.linear_mps >= v_lo - kSameVelocity &&
                along_arc.linear_mps <= v_hi + kSameVelocity && start_clearance_m >= threshold_m &&
                start_clearance_m > 0.0;
    if (free && std::abs(v0) >= kSameVelocity) {
      const double arc_s = 0.5 * stop_s;
      const double dt_max_s = std::min(o.rollout_step_s, check_spacing_m / std::abs(v0));
      const int steps = std::max(1, static_cast<int>(std::ceil(arc_s / dt_max_s - 1e-9)));
      ArcStepper stepper(robot_in_map, v0, w0, arc_s / steps);
      for (int i = 0; i < steps && free; ++i) {
        stepper.Step();
        const double clearance_m = obstacles.ClearanceM(stepper.position());
        free = clearance_m >= threshold_m && clearance_m > 0.0;
        poses.push_back(stepper.pose());
      }
    }
    out->found = free;
    out->braking = free;
    out->command = free ? along_arc : brake;
    out->best_rollout = free ? std::move(poses) : Rollout(robot_in_map, brake);
  };

  DwaResult result;
  if (path_m.empty()) {
    BrakeAlongArc(&result);  // no goal: stop
    result.trajectories_evaluated = 1;
    result.trajectories_colliding = result.found ? 0 : 1;
    return result;
  }

  const std::vector<double> v_samples = Samples(v_lo, v_hi, o.linear_samples, v_hi, 0.0);
  const std::vector<double> w_samples = Samples(w_lo, w_hi, o.angular_samples, 0.0, 0.0);

  const double reach_m = std::max(o.max_linear_mps, -o.min_linear_mps) * o.horizon_s;
  const LocalPath local =
      MakeLocalPath(start, path_m, o.goal_lookahead_m, std::max(o.goal_lookahead_m, reach_m) + 0.5);

  struct Candidate {
    DwaVelocity velocity;
    std::array<double, 4> cost;  // path alignment, goal heading, clearance, speed
  };
  std::vector<Candidate> candidates;
  candidates.reserve(v_samples.size() * w_samples.size());
  for (double v : v_samples) {
    for (double w : w_samples) {
      ++result.trajectories_evaluated;
      const double clearance_m = rollout_clearance(v, w);
      if (std::isnan(clearance_m)) {
        ++result.trajectories_colliding;
        continue;
      }
      const Pose2d end = ArcPose(robot_in_map, v, w, o.horizon_s);
      const Point2d end_point{end.x_m, end.y_m};
      // Heading as Fox et al.: where the robot stops if it brakes after this
      // period, so it turns at full rate until braking lands on the target
      // (at the horizon's end it would creep, as w * horizon_s overshoots).
      const Pose2d stop = ArcPose(robot_in_map, v, w, o.control_period_s + 0.5 * braking_s(v, w));
      const double to_lookahead_m = Distance({stop.x_m, stop.y_m}, local.lookahead);
      const double heading_error_rad =
          to_lookahead_m < 1e-6 ? 0.0
                                : std::abs(WrapAngle(std::atan2(local.lookahead.y_m - stop.y_m,
                                                                local.lookahead.x_m - stop.x_m) -
                                                     stop.yaw_rad));
      Candidate candidate;
      candidate.velocity = {v, w};
      candidate.cost = {DistanceToPolyline(end_point, local.points), heading_error_rad / M_PI,
                        o.clearance_cap_m - std::min(clearance_m, o.clearance_cap_m),
                        1.0 - v / o.max_linear_mps};
      candidates.push_back(candidate);
    }
  }

  if (candidates.empty()) {
    // The horizon slides forward each cycle, so last cycle's free arc can
    // collide now at its far end; braking along it is what that guaranteed.
    BrakeAlongArc(&result);
    return result;
  }

  // Min-max normalise each term over the candidates so the weights compare.
  const std::array<double, 4> weights = {o.weight_path_alignment, o.weight_goal_heading,
                                         o.weight_clearance, o.weight_speed};
  std::array<double, 4> lo, scale;
  for (int k = 0; k < 4; ++k) {
    double min_cost = std::numeric_limits<double>::infinity();
    double max_cost = -min_cost;
    for (const Candidate& c : candidates) {
      min_cost = std::min(min_cost, c.cost[k]);
      max_cost = std::max(max_cost, c.cost[k]);
    }
    lo[k] = min_cost;
    scale[k] = max_cost - min_cost > kFlatTerm ? weights[k] / (max_cost - min_cost) : 0.0;
  }
  const Candidate* best = nullptr;
  double best_score = std::numeric_limits<double>::infinity();
  for (const Candidate& c : candidates) {
    double score = 0.0;
    for (int k = 0; k < 4; ++k) score += (c.cost[k] - lo[k]) * scale[k];
    // Ties (e.g. standing on the goal) go to the least turning: no spinning in place for nothing.
    const bool tie = best != nullptr && std::abs(score - best_score) < 1e-12;
    if ((!tie && score < best_score) ||
        (tie && std::abs(c.velocity.angular_radps) < std::abs(best->velocity.angular_radps))) {
      best_score = score;
      best = &c;
    }
  }
  result.found = true;
  result.command = best->velocity;
  result.score = best_score;
  result.best_rollout = Rollout(robot_in_map, result.command);
  return result;
}

}  // namespace aslam
