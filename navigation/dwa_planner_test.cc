#include "navigation/dwa_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace aslam {
namespace {

constexpr double kRes = 0.05;
constexpr double kHalfCell = 0.5 * kRes;

LocalObstacles PointObstacles(const std::vector<Point2d>& points, const Pose2d& robot) {
  return LocalObstacles(OccupancyGrid(), points, robot, LocalObstaclesOptions());
}

double NearestM(const Point2d& p, const std::vector<Point2d>& points) {
  double best = std::numeric_limits<double>::infinity();
  for (const Point2d& q : points) best = std::min(best, std::hypot(p.x_m - q.x_m, p.y_m - q.y_m));
  return best;
}

// A polyline through `corners`, one point per 5 cm as the global planner gives.
std::vector<Point2d> DensePath(const std::vector<Point2d>& corners) {
  std::vector<Point2d> path{corners.front()};
  for (std::size_t i = 1; i < corners.size(); ++i) {
    const Point2d a = corners[i - 1], b = corners[i];
    const int steps =
        std::max(1, static_cast<int>(std::ceil(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) / kRes)));
    for (int k = 1; k <= steps; ++k) {
      path.push_back({a.x_m + (b.x_m - a.x_m) * k / steps, a.y_m + (b.y_m - a.y_m) * k / steps});
    }
  }
  return path;
}

// A straight wall of points from a to b, 2 cm apart.
void AddWall(const Point2d& a, const Point2d& b, std::vector<Point2d>* points) {
  const int n = static_cast<int>(std::ceil(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) / 0.02));
  for (int k = 0; k <= n; ++k) {
    points->push_back({a.x_m + (b.x_m - a.x_m) * k / n, a.y_m + (b.y_m - a.y_m) * k / n});
  }
}

// The closed-form pose after t_s at constant (v, w).
Pose2d ClosedFormArc(const Pose2d& start, double v, double w, double t_s) {
  if (w == 0.0) {
    return {start.x_m + v * t_s * std::cos(start.yaw_rad),
            start.y_m + v * t_s * std::sin(start.yaw_rad), start.yaw_rad};
  }
  const double yaw = start.yaw_rad + w * t_s;
  return {start.x_m + v / w * (std::sin(yaw) - std::sin(start.yaw_rad)),
          start.y_m - v / w * (std::cos(yaw) - std::cos(start.yaw_rad)), WrapAngle(yaw)};
}

void ExpectInDynamicWindow(const DwaOptions& o, const DwaVelocity& current,
                           const DwaVelocity& command) {
  const double v0 = std::clamp(current.linear_mps, o.min_linear_mps, o.max_linear_mps);
  const double w0 = std::clamp(current.angular_radps, -o.max_angular_radps, o.max_angular_radps);
  const double dv = o.max_linear_accel_mps2 * o.control_period_s;
  const double dw = o.max_angular_accel_radps2 * o.control_period_s;
  EXPECT_LE(std::abs(command.linear_mps - v0), dv + 1e-9);
  EXPECT_LE(std::abs(command.angular_radps - w0), dw + 1e-9);
  EXPECT_GE(command.linear_mps, o.min_linear_mps - 1e-12);
  EXPECT_LE(command.linear_mps, o.max_linear_mps + 1e-12);
  EXPECT_LE(std::abs(command.angular_radps), o.max_angular_radps + 1e-12);
}

// Drives the ideal kinematics (velocity = command) for `cycles` control
// periods; returns the poses and fails if the robot ever gets closer than
// radius + margin - half a cell to a point.
struct Drive {
  std::vector<Pose2d> poses;
  DwaVelocity velocity;
  int not_found = 0;
  int braking = 0;
};
Drive DriveClosedLoop(const DwaPlanner& planner, Pose2d pose, const std::vector<Point2d>& obstacles,
                      const std::vector<Point2d>& path, int cycles, double stop_within_m = 0.0) {
  const DwaOptions& o = planner.options();
  Drive drive;
  drive.poses.push_back(pose);
  for (int i = 0; i < cycles; ++i) {
    if (stop_within_m > 0.0 &&
        std::hypot(pose.x_m - path.back().x_m, pose.y_m - path.back().y_m) < stop_within_m) {
      break;
    }
    const DwaResult result =
        planner.Plan(pose, drive.velocity, path, PointObstacles(obstacles, pose));
    if (!result.found) ++drive.not_found;
    if (result.braking) ++drive.braking;
    ExpectInDynamicWindow(o, drive.velocity, result.command);
    drive.velocity = result.command;
    // Check the motion of this period finely, not only where it ends.
    for (int k = 1; k <= 10; ++k) {
      const Pose2d p = ClosedFormArc(pose, drive.velocity.linear_mps, drive.velocity.angular_radps,
                                     o.control_period_s * k / 10);
      EXPECT_GE(NearestM({p.x_m, p.y_m}, obstacles),
                o.robot_radius_m + o.safety_margin_m - kHalfCell)
          << "cycle " << i;
    }
    pose = ClosedFormArc(pose, drive.velocity.linear_mps, drive.velocity.angular_radps,
                         o.control_period_s);
    drive.poses.push_back(pose);
  }
  return drive;
}

// Braking from `current` with v and w slowed together follows the current
// arc for what `current` covers in half the stopping time.
void ExpectBrakingPathFree(const DwaOptions& o, const Pose2d& robot, const DwaVelocity& current,
                           const std::vector<Point2d>& points) {
  const double stop_s = std::max(std::abs(current.linear_mps) / o.max_linear_accel_mps2,
                                 std::abs(current.angular_radps) / o.max_angular_accel_radps2);
  for (int k = 0; k <= 100; ++k) {
    const Pose2d p =
        ClosedFormArc(robot, current.linear_mps, current.angular_radps, 0.5 * stop_s * k / 100);
    ASSERT_GE(NearestM({p.x_m, p.y_m}, points), o.robot_radius_m + o.safety_margin_m - kHalfCell);
  }
}

TEST(DwaPlannerTest, RolloutIsAnExactArc) {
  const DwaPlanner planner{DwaOptions()};
  const Pose2d start{1.0, -2.0, 2.9};
  for (const DwaVelocity velocity :
       {DwaVelocity{0.5, 0.0}, DwaVelocity{0.5, 1.8}, DwaVelocity{0.3, -0.7}, DwaVelocity{0.0, 1.2},
        DwaVelocity{0.4, 5e-6}, DwaVelocity{-0.2, 0.5}}) {
    const std::vector<Pose2d> poses = planner.Rollout(start, velocity);
    ASSERT_EQ(poses.size(), 21u);  // start + 2 s / 0.1 s
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Pose2d expected =
          ClosedFormArc(start, velocity.linear_mps, velocity.angular_radps, 0.1 * i);
      EXPECT_NEAR(poses[i].x_m, expected.x_m, 1e-9) << "w " << velocity.angular_radps << " i " << i;
      EXPECT_NEAR(poses[i].y_m, expected.y_m, 1e-9) << "w " << velocity.angular_radps << " i " << i;
      EXPECT_NEAR(WrapAngle(poses[i].yaw_rad - expected.yaw_rad), 0.0, 1e-9);
    }
  }
  // A horizon that is not a whole number of steps ends exactly at the horizon.
  DwaOptions options;
  options.horizon_s = 1.05;
  const std::vector<Pose2d> poses = DwaPlanner(options).Rollout(start, {0.5, 1.0});
  ASSERT_EQ(poses.size(), 12u);
  const Pose2d expected = ClosedFormArc(start, 0.5, 1.0, 1.05);
  EXPECT_NEAR(poses.back().x_m, expected.x_m, 1e-9);
  EXPECT_NEAR(poses.back().y_m, expected.y_m, 1e-9);
}

// Hundreds of random point-obstacle sets, start velocities and paths: the
// chosen command's rollout never comes within radius + margin (less half a
// cell) of a point, and the command lies in the dynamic window.
TEST(DwaPlannerTest, NeverSelectsACollidingTrajectory) {
  const DwaOptions options;
  const DwaPlanner planner(options);
  DwaOptions fine_options = options;
  fine_options.rollout_step_s = 0.01;  // recheck the chosen arc every 5 mm
  const DwaPlanner fine(fine_options);
  const double required_m = options.robot_radius_m + options.safety_margin_m;

  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int planned = 0, found = 0, moving = 0, braking = 0;
  while (planned < 400) {
    const Pose2d robot{4.0 * unit(rng) - 2.0, 4.0 * unit(rng) - 2.0, 6.0 * unit(rng) - 3.0};
    std::vector<Point2d> points;
    const int count = 3 + static_cast<int>(unit(rng) * 60);
    for (int i = 0; i < count; ++i) {
      points.push_back({robot.x_m + 3.0 * unit(rng) - 1.5, robot.y_m + 3.0 * unit(rng) - 1.5});
    }
    if (unit(rng) < 0.3) {  // sometimes a wall
      const Point2d a{robot.x_m + 2.0 * unit(rng) - 1.0, robot.y_m + 2.0 * unit(rng) - 1.0};
      AddWall(a, {a.x_m + 2.0 * unit(rng) - 1.0, a.y_m + 2.0 * unit(rng) - 1.0}, &points);
    }
    // Start clearly outside the margin (the escape rule is tested below).
    if (NearestM({robot.x_m, robot.y_m}, points) < required_m + 2 * kRes) continue;
    const Point2d goal{robot.x_m + 6.0 * unit(rng) - 3.0, robot.y_m + 6.0 * unit(rng) - 3.0};
    const Point2d via{robot.x_m + 2.0 * unit(rng) - 1.0, robot.y_m + 2.0 * unit(rng) - 1.0};
    const std::vector<Point2d> path = DensePath({{robot.x_m, robot.y_m}, via, goal});
    const DwaVelocity current{options.max_linear_mps * unit(rng),
                              options.max_angular_radps * (2.0 * unit(rng) - 1.0)};
    ++planned;

    const DwaResult result = planner.Plan(robot, current, path, PointObstacles(points, robot));
    EXPECT_GE(result.trajectories_evaluated, 231);  // 11 x 21, plus v = 0 or w = 0 if in the window
    EXPECT_LE(result.trajectories_evaluated, 12 * 22);
    ExpectInDynamicWindow(options, current, result.command);
    if (!result.found) continue;
    ++found;
    if (result.braking) {
      ++braking;
      ExpectBrakingPathFree(options, robot, current, points);
      continue;
    }
    if (result.command.linear_mps > 0.1) ++moving;
    for (const Pose2d& pose : fine.Rollout(robot, result.command)) {
      ASSERT_GE(NearestM({pose.x_m, pose.y_m}, points), required_m - kHalfCell)
          << "trial " << planned << " command " << result.command.linear_mps << ", "
          << result.command.angular_radps;
    }
  }
  // The test means something only if most plans found a way and many moved.
  EXPECT_GT(found, 300);
  EXPECT_GT(moving, 100);
  EXPECT_GT(braking, 0);  // the fallback was exercised too
  RecordProperty("found", found);
  RecordProperty("braking", braking);
}

TEST(DwaPlannerTest, FreeSpaceGoalAheadDrivesAtNearMaxSpeed) {
  const DwaPlanner planner{DwaOptions()};
  const std::vector<Point2d> path = DensePath({{0.0, 0.0}, {8.0, 0.0}});
  // Already at speed: keep it.
  const DwaResult cruising =
      planner.Plan({0.0, 0.0, 0.0}, {0.5, 0.0}, path, PointObstacles({}, {}));
  ASSERT_TRUE(cruising.found);
  EXPECT_NEAR(cruising.command.linear_mps, 0.5, 1e-9);
  EXPECT_NEAR(cruising.command.angular_radps, 0.0, 1e-9);
  // From rest: accelerates straight to near max speed within a second.
  const Drive drive = DriveClosedLoop(planner, {0.0, 0.0, 0.0}, {}, path, 10);
  EXPECT_GE(drive.velocity.linear_mps, 0.45);
  EXPECT_LT(std::abs(drive.velocity.angular_radps), 0.1);
  EXPECT_LT(std::abs(drive.poses.back().y_m), 0.02);
}

TEST(DwaPlannerTest, GoalBehindTurnsInPlaceTowardIt) {
  const DwaPlanner planner{DwaOptions()};
  for (const double side : {1.0, -1.0}) {
    // Goal behind and a little to the left (right): turn left (right).
    const std::vector<Point2d> path = DensePath({{0.0, 0.0}, {-3.0, side * 0.3}});
    const DwaResult result = planner.Plan({0.0, 0.0, 0.0}, {}, path, PointObstacles({}, {}));
    ASSERT_TRUE(result.found);
    EXPECT_EQ(result.command.linear_mps, 0.0);
    EXPECT_NEAR(result.command.angular_radps, side * 0.3, 1e-9);  // all the window allows
    // Already turning: the window's exact edge, v = 0 and w = ±max, is a sample.
    const DwaResult turning =
        planner.Plan({0.0, 0.0, 0.0}, {0.0, side * 1.7}, path, PointObstacles({}, {}));
    EXPECT_EQ(turning.command.linear_mps, 0.0);
    EXPECT_EQ(turning.command.angular_radps, side * 1.8);
    // Keeps turning (at most creeping) until it faces the goal.
    const Drive drive = DriveClosedLoop(planner, {0.0, 0.0, 0.0}, {}, path, 20);
    EXPECT_LT(std::hypot(drive.poses.back().x_m, drive.poses.back().y_m), 0.1);
    EXPECT_GT(std::abs(drive.poses.back().yaw_rad), 2.0);
    EXPECT_GT(side * drive.poses.back().yaw_rad, 0.0);
  }
}

TEST(DwaPlannerTest, FacingAWallTurnsAndGoesAroundIt) {
  const DwaOptions options;
  const DwaPlanner planner(options);
  // Robot on a cell centre 0.3 m from a 2 m wall across its heading; the goal
  // is behind the wall and the path goes around its left end.
  const Pose2d robot{0.025, 0.025, 0.0};
  std::vector<Point2d> wall;
  AddWall({0.325, -1.0}, {0.325, 1.0}, &wall);
  const std::vector<Point2d> path =
      DensePath({{robot.x_m, robot.y_m}, {0.0, 1.6}, {1.0, 1.6}, {1.0, 0.0}});

  const DwaResult first = planner.Plan(robot, {}, path, PointObstacles(wall, robot));
  ASSERT_TRUE(first.found);
  EXPECT_GT(first.command.angular_radps, 0.2);  // turns left, toward the path
  for (const Pose2d& pose : first.best_rollout) {
    EXPECT_LE(pose.x_m, robot.x_m + 0.03);  // not toward the wall
  }
  // Closed loop: never touches the wall and ends up at the goal behind it.
  const Drive drive = DriveClosedLoop(planner, robot, wall, path, 200, 0.3);
  EXPECT_LT(std::hypot(drive.poses.back().x_m - 1.0, drive.poses.back().y_m), 0.3);
  EXPECT_EQ(drive.not_found, 0);  // never "stuck" on the way
}

TEST(DwaPlannerTest, AllBlockedReportsNotFound) {
  const DwaOptions options;
  std::vector<Point2d> wall;
  AddWall({0.375, -2.0}, {0.375, 2.0}, &wall);
  const Pose2d robot{0.025, 0.025, 0.0};
  const std::vector<Point2d> path = DensePath({{robot.x_m, robot.y_m}, {3.0, 0.0}});
  // Full speed at a wall 0.35 m ahead: no command in the window avoids it.
  const DwaResult fast =
      DwaPlanner(options).Plan(robot, {0.5, 0.0}, path, PointObstacles(wall, robot));
  EXPECT_FALSE(fast.found);
  EXPECT_EQ(fast.trajectories_colliding, fast.trajectories_evaluated);
  EXPECT_NEAR(fast.command.linear_mps, 0.4, 1e-9);  // brakes as hard as it can
  EXPECT_NEAR(fast.command.angular_radps, 0.0, 1e-9);

  EXPECT_FALSE(fast.braking);

  // Boxed in closer than radius + margin, with the escape rule off.
  std::vector<Point2d> box;
  AddWall({-0.2, -0.2}, {0.2, -0.2}, &box);
  AddWall({0.2, -0.2}, {0.2, 0.2}, &box);
  AddWall({0.2, 0.2}, {-0.2, 0.2}, &box);
  AddWall({-0.2, 0.2}, {-0.2, -0.2}, &box);
  DwaOptions strict = options;
  strict.escape_inside_margin = false;
  const DwaResult boxed =
      DwaPlanner(strict).Plan({0.0, 0.0, 0.0}, {}, path, PointObstacles(box, {}));
  EXPECT_FALSE(boxed.found);
  EXPECT_EQ(boxed.trajectories_colliding, boxed.trajectories_evaluated);
  // An empty obstacle layer blocks everything too.
  EXPECT_FALSE(DwaPlanner(options).Plan(robot, {}, path, LocalObstacles()).found);
}

TEST(DwaPlannerTest, WhenOnlyBrakingIsFreeItBrakesAlongItsArc) {
  const DwaOptions options;
  // Full speed, a wall 0.875 m ahead: every sample over 2 s reaches it, but
  // braking (0.125 m) does not.
  std::vector<Point2d> wall;
  AddWall({0.9, -3.0}, {0.9, 3.0}, &wall);
  const Pose2d robot{0.025, 0.025, 0.0};
  const std::vector<Point2d> path = DensePath({{robot.x_m, robot.y_m}, {3.0, 0.0}});
  const DwaVelocity current{0.5, 0.1};
  const DwaResult result =
      DwaPlanner(options).Plan(robot, current, path, PointObstacles(wall, robot));
  ASSERT_TRUE(result.found);
  EXPECT_TRUE(result.braking);
  EXPECT_EQ(result.trajectories_colliding, result.trajectories_evaluated);
  EXPECT_NEAR(result.command.linear_mps, 0.4, 1e-9);      // slowed by a * period...
  EXPECT_NEAR(result.command.angular_radps, 0.08, 1e-9);  // ...and w in proportion
  ExpectInDynamicWindow(options, current, result.command);
  ExpectBrakingPathFree(options, robot, current, wall);
  ASSERT_FALSE(result.best_rollout.empty());
  EXPECT_NEAR(result.best_rollout.back().x_m, robot.x_m + 0.125, 0.01);
}

TEST(DwaPlannerTest, InsideTheMarginItMovesAwayWithoutGettingCloser) {
  const DwaOptions options;
  const DwaPlanner planner(options);
  const std::vector<Point2d> obstacle{{0.15, 0.0}};  // 0.15 m ahead: inside radius + margin
  const std::vector<Point2d> path = DensePath({{0.0, 0.0}, {-2.0, 0.5}});
  const double start_m = NearestM({0.0, 0.0}, obstacle);
  Pose2d pose{0.0, 0.0, 0.0};
  DwaVelocity velocity;
  for (int i = 0; i < 40; ++i) {
    const DwaResult result = planner.Plan(pose, velocity, path, PointObstacles(obstacle, pose));
    ASSERT_TRUE(result.found) << "cycle " << i;
    for (const Pose2d& p : result.best_rollout) {
      EXPECT_GE(NearestM({p.x_m, p.y_m}, obstacle), start_m - kRes) << "cycle " << i;
    }
    velocity = result.command;
    pose = ClosedFormArc(pose, velocity.linear_mps, velocity.angular_radps, 0.1);
  }
  EXPECT_GT(NearestM({pose.x_m, pose.y_m}, obstacle),
            options.robot_radius_m + options.safety_margin_m);
}

TEST(DwaPlannerTest, EmptyPathBrakesAndAtTheGoalItStops) {
  const DwaPlanner planner{DwaOptions()};
  const DwaResult no_path = planner.Plan({0.0, 0.0, 0.0}, {0.3, 0.5}, {}, PointObstacles({}, {}));
  EXPECT_TRUE(no_path.found);
  EXPECT_TRUE(no_path.braking);
  EXPECT_NEAR(no_path.command.linear_mps, 0.2, 1e-9);  // stops in 0.3 s: 1/3 off per period
  EXPECT_NEAR(no_path.command.angular_radps, 0.5 * 2.0 / 3.0, 1e-9);  // same arc

  // Standing on the goal (one-point path): no creeping, no spinning.
  const DwaResult at_goal =
      planner.Plan({1.0, 1.0, 0.5}, {}, {{1.0, 1.0}}, PointObstacles({}, {1.0, 1.0, 0.5}));
  ASSERT_TRUE(at_goal.found);
  EXPECT_EQ(at_goal.command.linear_mps, 0.0);
  EXPECT_EQ(at_goal.command.angular_radps, 0.0);

  // Approaching the goal it slows down instead of overshooting.
  const std::vector<Point2d> path = DensePath({{0.0, 0.0}, {1.5, 0.0}});
  const Drive drive = DriveClosedLoop(planner, {0.0, 0.0, 0.0}, {}, path, 80);
  EXPECT_LT(std::hypot(drive.poses.back().x_m - 1.5, drive.poses.back().y_m), 0.15);
  EXPECT_LT(std::abs(drive.velocity.linear_mps), 0.15);
}

TEST(DwaPlannerTest, BadOptionsThrowNamingTheOption) {
  DwaOptions options;
  options.horizon_s = 0.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.linear_samples = 0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.min_linear_mps = 1.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.weight_speed = -1.0;
  try {
    options.Validate();
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("weight_speed"), std::string::npos);
  }
  EXPECT_NO_THROW(DwaOptions().Validate());
}

}  // namespace
}  // namespace aslam
