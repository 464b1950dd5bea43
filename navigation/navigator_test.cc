#include "navigation/navigator.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace aslam {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kCycleUs = 100'000;  // the scan period

// A 10 m x 10 m room with 0.15 m walls, 0.05 m cells; `divider` adds a wall
// at x = 5 m with gaps at y in [2, 3] (south) and [7, 8] (north).
OccupancyGrid Room(bool divider = false, bool south_gap = true) {
  OccupancyGrid grid(200, 200, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int i = 0; i < 200; ++i) {
    for (int t = 0; t < 3; ++t) {
      grid.at({i, t}) = grid.at({i, 199 - t}) = grid.at({t, i}) = grid.at({199 - t, i}) = 100;
    }
  }
  if (divider) {
    for (int row = 0; row < 200; ++row) {
      const double y = (row + 0.5) * 0.05;
      const bool in_gap = (south_gap && y > 2.0 && y < 3.0) || (y > 7.0 && y < 8.0);
      if (in_gap) continue;
      for (int col = 99; col < 102; ++col) grid.at({col, row}) = 100;
    }
  }
  return grid;
}

StampedPose PoseAt(int64_t utime, const Pose2d& pose) { return {utime, pose, 0.0, 0.0}; }

// How far north the current path reaches: which of Room's divider gaps it goes through.
double MaxPathY(const Navigator& navigator) {
  double y = 0.0;
  for (const Point2d& p : navigator.path_m()) y = std::max(y, p.y_m);
  return y;
}

// Drives a unicycle exactly along the commanded arc, no dynamics, no collisions.
Pose2d Integrate(const Pose2d& pose, const VelocityCommand& command, double dt_s) {
  Pose2d next = pose;
  constexpr int kSubsteps = 10;
  for (int i = 0; i < kSubsteps; ++i) {
    const double h = dt_s / kSubsteps;
    next.x_m += command.linear_mps * std::cos(next.yaw_rad) * h;
    next.y_m += command.linear_mps * std::sin(next.yaw_rad) * h;
    next.yaw_rad = WrapAngle(next.yaw_rad + command.angular_radps * h);
  }
  return next;
}

// Closes the loop over the kinematic robot for up to `seconds`, until the goal settles.
struct Drive {
  explicit Drive(Pose2d start) : pose(start) {}
  Pose2d pose;
  int64_t utime = 0;
  std::vector<NavOutput> outputs;
  double min_wall_clearance_m = 1e9;

  void Run(Navigator& navigator, double seconds) {
    const int64_t end = utime + static_cast<int64_t>(seconds * 1e6);
    while (utime < end) {
      utime += kCycleUs;
      navigator.SetPose(PoseAt(utime, pose));
      const NavOutput out = navigator.Step(utime);
      outputs.push_back(out);
      if (out.status.state != NavState::kActive) return;
      pose = Integrate(pose, out.command, kCycleUs * 1e-6);
      min_wall_clearance_m = std::min({min_wall_clearance_m, pose.x_m - 0.15, 9.85 - pose.x_m,
                                       pose.y_m - 0.15, 9.85 - pose.y_m});
    }
  }
};

// The planner's promise to the DWA: every cell the robot's centre may occupy on a plan is clear
// of every obstacle by the robot radius plus the safety margin, as the DWA measures clearance.
TEST(Navigator, EveryCellThePlannerMayEnterIsClearForTheDwa) {
  const NavOptions options = LoadNavOptionsFromFile("");
  const double needed_m = options.dwa.robot_radius_m + options.dwa.safety_margin_m;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial) {
    OccupancyGrid grid(60, 60, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
    for (int8_t& value : grid.mutable_cells()) {
      if (u01(rng) < 0.01) value = OccupancyGrid::kOccupied;
    }
    const Costmap costmap(grid, options.costmap);
    LocalObstaclesOptions window = options.local_obstacles;
    window.window_m = 6.0;  // the whole grid, from its centre
    const LocalObstacles obstacles(grid, {}, {1.5, 1.5, 0.0}, window);
    for (int row = 0; row < 60; ++row) {
      for (int col = 0; col < 60; ++col) {
        if (!costmap.Traversable({col, row})) continue;
        EXPECT_GE(obstacles.ClearanceM(costmap.CellCenter({col, row})), needed_m - 1e-6)
            << "trial " << trial << " cell " << col << "," << row;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 5000);
}

TEST(Navigator, IdleWithoutGoalCommandsZero) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  navigator.SetPose(PoseAt(kCycleUs, {2.0, 5.0, 0.0}));
  const NavOutput out = navigator.Step(kCycleUs);
  EXPECT_EQ(out.status.state, NavState::kIdle);
  EXPECT_EQ(out.status.goal_id, -1);
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_EQ(out.command.angular_radps, 0.0);
  EXPECT_EQ(out.command.utime, kCycleUs);
}

TEST(Navigator, DrivesToTheGoalAndReportsReached) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  Drive drive{{2.0, 5.0, M_PI / 2}};  // facing away from the goal's line
  navigator.SetGoal(7, {7.5, 3.0}, 0);
  drive.Run(navigator, 60.0);
  ASSERT_FALSE(drive.outputs.empty());
  const NavOutput& last = drive.outputs.back();
  EXPECT_EQ(last.status.state, NavState::kReached) << last.status.detail;
  EXPECT_EQ(last.status.goal_id, 7);
  EXPECT_EQ(last.command.linear_mps, 0.0);
  EXPECT_EQ(last.command.angular_radps, 0.0);
  EXPECT_LE(std::hypot(drive.pose.x_m - 7.5, drive.pose.y_m - 3.0), 0.3 + 0.05);
  EXPECT_EQ(last.status.recoveries_used, 0);
  EXPECT_GE(last.status.distance_remaining_m, 0.0);
  EXPECT_GT(drive.min_wall_clearance_m, 0.2);
  EXPECT_TRUE(drive.outputs.front().replanned);
  // Straight-line 5.9 m at <= 0.5 m/s: at least 12 s; the first replan was at 1 Hz thereafter.
  EXPECT_GT(drive.outputs.size(), 110u);
  EXPECT_GE(navigator.replans(), 10);
  // Distance remaining falls along the way (it is measured along the path).
  EXPECT_GT(drive.outputs[5].status.distance_remaining_m,
            drive.outputs[drive.outputs.size() / 2].status.distance_remaining_m);
  // Later steps stay reached and stopped.
  navigator.SetPose(PoseAt(drive.utime + kCycleUs, drive.pose));
  EXPECT_EQ(navigator.Step(drive.utime + kCycleUs).status.state, NavState::kReached);
}

TEST(Navigator, FacingAwayFromThePathItTurnsInPlaceFirst) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  Drive drive(Pose2d{2.0, 5.0, M_PI});  // the goal is straight behind
  navigator.SetGoal(1, {8.0, 5.0}, 0);
  drive.Run(navigator, 30.0);
  ASSERT_EQ(drive.outputs.back().status.state, NavState::kReached);
  std::size_t i = 0;
  for (; i < drive.outputs.size() && drive.outputs[i].command.linear_mps == 0.0; ++i) {
    EXPECT_GT(std::abs(drive.outputs[i].command.angular_radps), 0.2) << i;
  }
  EXPECT_GT(i, 10u);  // about pi at up to 1.5 rad/s
  EXPECT_LT(i, 40u);
  // It drives off only once roughly facing the goal, and never circles: 6 m of path, < 7 m driven.
  double driven_m = 0.0;
  Pose2d previous{2.0, 5.0, M_PI};
  for (const NavOutput& out : drive.outputs) {
    const Pose2d next = Integrate(previous, out.command, kCycleUs * 1e-6);
    driven_m += std::hypot(next.x_m - previous.x_m, next.y_m - previous.y_m);
    previous = next;
  }
  EXPECT_LT(driven_m, 7.0);
}

TEST(Navigator, GoalInAWallIsUnreachable) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  navigator.SetPose(PoseAt(0, {2.0, 5.0, 0.0}));
  navigator.SetGoal(1, {0.05, 5.0}, 0);  // inside the west wall
  const NavOutput out = navigator.Step(kCycleUs);
  EXPECT_EQ(out.status.state, NavState::kUnreachable);
  EXPECT_THAT(out.status.detail, HasSubstr("obstacle"));
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_EQ(out.status.distance_remaining_m, -1.0);
  EXPECT_TRUE(navigator.path_m().empty());

  navigator.SetGoal(2, {20.0, 5.0}, kCycleUs);
  EXPECT_THAT(navigator.Step(2 * kCycleUs).status.detail, HasSubstr("outside the map"));
}

TEST(Navigator, AGoalOnAWallsFaceIsApproachedWhereTheRobotSeesIt) {
  // A frontier target that a newer map drew the wall over: the robot looks at it from the
  // nearest cell it can stand on, as the utility planned when it chose the goal.
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  const Point2d goal{9.875, 5.0};  // the east wall's inner cell
  ASSERT_EQ(Room().at(Room().WorldToCell(goal)), 100);
  Drive drive{{2.0, 5.0, 0.0}};
  navigator.SetGoal(1, goal, 0);
  drive.Run(navigator, 60.0);
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
  EXPECT_GT(drive.min_wall_clearance_m, 0.2);
  EXPECT_LT(std::hypot(drive.pose.x_m - goal.x_m, drive.pose.y_m - goal.y_m),
            NavOptions{}.navigator.goal_snap_m + NavOptions{}.navigator.goal_tolerance_m);
}

TEST(Navigator, GoalWithoutAPathIsUnreachable) {
  OccupancyGrid map = Room();
  // A closed box around (7, 7).
  for (int i = 120; i <= 160; ++i) {
    for (int t = 0; t < 3; ++t) {
      map.at({i, 120 + t}) = map.at({i, 160 - t}) = map.at({120 + t, i}) = map.at({160 - t, i}) =
          100;
    }
  }
  Navigator navigator{NavOptions{}};
  navigator.SetMap(map);
  navigator.SetPose(PoseAt(0, {2.0, 5.0, 0.0}));
  navigator.SetGoal(1, {7.0, 7.0}, 0);
  const NavStatus status = navigator.Step(kCycleUs).status;
  EXPECT_EQ(status.state, NavState::kUnreachable);
  EXPECT_THAT(status.detail, HasSubstr("no path"));
}

TEST(Navigator, GoalBesideAWallIsPlannedToTheNearestFreeCell) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  navigator.SetPose(PoseAt(0, {2.0, 5.0, 0.0}));
  // 0.22 m from the wall's face: inscribed (0.20 m radius), but within the snap distance.
  navigator.SetGoal(1, {9.63, 5.0}, 0);
  const NavStatus status = navigator.Step(kCycleUs).status;
  EXPECT_EQ(status.state, NavState::kActive) << status.detail;
  ASSERT_FALSE(navigator.path_m().empty());
  EXPECT_NEAR(navigator.path_m().back().x_m, 9.63, 0.15);
}

TEST(Navigator, NoProgressRotatesBacksOffThenFails) {
  NavOptions options;
  options.navigator.progress_timeout_s = 2.0;
  options.navigator.max_recoveries = 1;
  Navigator navigator{options};
  navigator.SetMap(Room());
  const Pose2d stuck{2.0, 5.0, M_PI};  // a base that never moves, facing away from the goal
  navigator.SetGoal(3, {8.0, 5.0}, 0);
  std::vector<NavOutput> outputs;
  for (int64_t utime = kCycleUs; utime < 60'000'000; utime += kCycleUs) {
    navigator.SetPose(PoseAt(utime, stuck));
    outputs.push_back(navigator.Step(utime));
    if (outputs.back().status.state != NavState::kActive) break;
  }
  ASSERT_EQ(outputs.back().status.state, NavState::kFailed);
  EXPECT_THAT(outputs.back().status.detail, HasSubstr("no progress"));
  EXPECT_THAT(outputs.back().status.detail, HasSubstr("after 1 recoveries"));
  EXPECT_EQ(outputs.back().command.linear_mps, 0.0);
  EXPECT_EQ(outputs.back().command.angular_radps, 0.0);

  // The phases in order, each commanding what it should.
  std::vector<RecoveryPhase> phases;
  for (const NavOutput& out : outputs) {
    if (phases.empty() || phases.back() != out.status.recovery)
      phases.push_back(out.status.recovery);
    if (out.status.recovery == RecoveryPhase::kRotate) {
      EXPECT_EQ(out.command.linear_mps, 0.0);
      EXPECT_GT(std::abs(out.command.angular_radps), 0.1);
      EXPECT_THAT(out.status.detail, HasSubstr("recovering: no progress"));
    }
    if (out.status.recovery == RecoveryPhase::kBackOff) {
      EXPECT_LT(out.command.linear_mps, 0.0);
      EXPECT_EQ(out.command.angular_radps, 0.0);
    }
  }
  EXPECT_EQ(phases, (std::vector<RecoveryPhase>{RecoveryPhase::kNone, RecoveryPhase::kRotate,
                                                RecoveryPhase::kBackOff, RecoveryPhase::kNone}));
  // Recovery started after the 2 s timeout, not before.
  std::size_t first_rotate = 0;
  while (outputs[first_rotate].status.recovery != RecoveryPhase::kRotate) ++first_rotate;
  EXPECT_NEAR(outputs[first_rotate].status.utime * 1e-6, 2.1, 0.15);
}

// Plans flipping between a short and a long route (here the south gap of the divider
// opening and closing every second) are not progress: a base that does not move
// starts its recovery after progress_timeout_s all the same.
TEST(Navigator, PlansFlippingBetweenRoutesAreNotProgress) {
  NavOptions options;
  options.navigator.progress_timeout_s = 2.0;
  Navigator navigator{options};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/true));
  const Pose2d stuck{2.0, 2.5, M_PI};  // never moves
  navigator.SetGoal(1, {8.0, 2.5}, 0);
  std::vector<double> path_lengths_m;
  int64_t recovery_utime = -1;
  for (int64_t utime = kCycleUs; utime < 8'000'000 && recovery_utime < 0; utime += kCycleUs) {
    if (utime % 1'000'000 == 0) {
      navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/(utime / 1'000'000) % 2 == 0));
    }
    navigator.SetPose(PoseAt(utime, stuck));
    const NavOutput out = navigator.Step(utime);
    ASSERT_EQ(out.status.state, NavState::kActive);
    if (out.replanned) path_lengths_m.push_back(navigator.path_length_m());
    if (out.status.recovery != RecoveryPhase::kNone) recovery_utime = utime;
  }
  // The routes did flip: about 6 m through the south gap, about 14 m round by the north.
  ASSERT_GE(path_lengths_m.size(), 3u);
  EXPECT_LT(*std::min_element(path_lengths_m.begin(), path_lengths_m.end()), 8.0);
  EXPECT_GT(*std::max_element(path_lengths_m.begin(), path_lengths_m.end()), 11.0);
  ASSERT_GT(recovery_utime, 0) << "flipping plans kept resetting the progress check";
  EXPECT_NEAR(recovery_utime * 1e-6, 2.1, 0.15);
}

TEST(Navigator, BackOffStopsWhenTheRearIsBlocked) {
  NavOptions options;
  options.navigator.progress_timeout_s = 1.0;
  Navigator navigator{options};
  navigator.SetMap(Room());
  // Facing the goal (east) with the west wall right behind: turning is pointless, backing off
  // unsafe.
  const Pose2d stuck{0.45, 5.0, 0.0};
  navigator.SetGoal(1, {5.0, 5.0}, 0);
  bool saw_back_off_command = false;
  bool saw_rotate = false;
  for (int64_t utime = kCycleUs; utime < 12'000'000; utime += kCycleUs) {
    navigator.SetPose(PoseAt(utime, stuck));
    const NavOutput out = navigator.Step(utime);
    saw_rotate |= out.status.recovery == RecoveryPhase::kRotate;
    saw_back_off_command |= out.command.linear_mps < 0.0;
  }
  EXPECT_TRUE(saw_rotate);
  EXPECT_FALSE(saw_back_off_command);
}

TEST(Navigator, CancelStopsAndIdles) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  Drive drive{{2.0, 5.0, 0.0}};
  navigator.SetGoal(5, {8.0, 5.0}, 0);
  drive.Run(navigator, 2.0);
  EXPECT_EQ(drive.outputs.back().status.state, NavState::kActive);
  EXPECT_GT(drive.outputs.back().command.linear_mps, 0.0);
  EXPECT_FALSE(navigator.path_m().empty());

  EXPECT_FALSE(navigator.Cancel(4, drive.utime));  // not the current goal
  EXPECT_EQ(navigator.status().state, NavState::kActive);
  const int64_t revision = navigator.path_revision();
  EXPECT_TRUE(navigator.Cancel(5, drive.utime));
  EXPECT_EQ(navigator.status().state, NavState::kIdle);
  EXPECT_GT(navigator.path_revision(), revision);
  EXPECT_TRUE(navigator.path_m().empty());
  const NavOutput out = navigator.Step(drive.utime + kCycleUs);
  EXPECT_EQ(out.status.state, NavState::kIdle);
  EXPECT_EQ(out.status.goal_id, 5);
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_EQ(out.command.angular_radps, 0.0);
}

TEST(Navigator, ResentGoalIsANoOpAndANewIdStartsOver) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  navigator.SetPose(PoseAt(0, {2.0, 5.0, 0.0}));
  navigator.SetGoal(1, {2.1, 5.0}, 0);
  EXPECT_EQ(navigator.Step(kCycleUs).status.state, NavState::kReached);
  navigator.SetGoal(1, {2.1, 5.0}, kCycleUs);
  EXPECT_EQ(navigator.Step(2 * kCycleUs).status.state, NavState::kReached);
  navigator.SetGoal(2, {8.0, 5.0}, 2 * kCycleUs);
  navigator.SetPose(PoseAt(3 * kCycleUs, {2.0, 5.0, 0.0}));
  const NavStatus status = navigator.Step(3 * kCycleUs).status;
  EXPECT_EQ(status.state, NavState::kActive);
  EXPECT_EQ(status.goal_id, 2);
  EXPECT_NEAR(status.distance_remaining_m, 6.0, 0.1);
}

TEST(Navigator, ReplansWhenTheMapBlocksThePath) {
  NavOptions options;
  options.navigator.replan_period_s = 1000.0;  // only the map change may trigger it
  Navigator navigator{options};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/true));
  const Pose2d robot{2.0, 2.5, 0.0};
  navigator.SetPose(PoseAt(kCycleUs, robot));
  navigator.SetGoal(1, {8.0, 2.5}, 0);
  NavOutput out = navigator.Step(kCycleUs);
  ASSERT_TRUE(out.replanned);
  EXPECT_LT(MaxPathY(navigator), 4.0);  // through the south gap
  const double direct_m = out.status.distance_remaining_m;

  navigator.SetPose(PoseAt(2 * kCycleUs, robot));
  EXPECT_FALSE(navigator.Step(2 * kCycleUs).replanned);
  navigator.SetMap(Room(true, true));  // unchanged: no replan
  navigator.SetPose(PoseAt(3 * kCycleUs, robot));
  EXPECT_FALSE(navigator.Step(3 * kCycleUs).replanned);

  navigator.SetMap(Room(true, /*south_gap=*/false));
  navigator.SetPose(PoseAt(4 * kCycleUs, robot));
  out = navigator.Step(4 * kCycleUs);
  EXPECT_TRUE(out.replanned);
  EXPECT_EQ(out.status.state, NavState::kActive);
  EXPECT_GT(MaxPathY(navigator), 6.5);  // through the north gap
  EXPECT_GT(out.status.distance_remaining_m, direct_m + 5.0);
}

// Plans use a goal-distance field made when the goal came. A gap that opens later is a wall gone
// from that field: the route through it is taken at the latest when the field is renewed (30 s).
TEST(Navigator, AWallGoneSinceTheGoalIsUsedOnceTheFieldIsRenewed) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/false));
  const Pose2d robot{2.0, 2.5, 0.0};
  navigator.SetPose(PoseAt(kCycleUs, robot));
  navigator.SetGoal(1, {8.0, 2.5}, 0);
  NavOutput out = navigator.Step(kCycleUs);
  ASSERT_TRUE(out.replanned);
  EXPECT_GT(MaxPathY(navigator), 6.5);  // through the north gap, the only one

  navigator.SetMap(Room(true, /*south_gap=*/true));
  for (int64_t utime = 2 * kCycleUs; utime <= 32'000'000; utime += kCycleUs) {
    navigator.SetPose(PoseAt(utime, robot));  // held in place: only the plans change
    out = navigator.Step(utime);
    ASSERT_EQ(out.status.state, NavState::kActive);
  }
  EXPECT_LT(MaxPathY(navigator), 4.0);  // through the south gap
}

TEST(Navigator, ReplansAtTheReplanPeriod) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  navigator.SetGoal(1, {8.0, 5.0}, 0);
  int replans = 0;
  for (int64_t utime = kCycleUs; utime <= 3'000'000; utime += kCycleUs) {
    navigator.SetPose(PoseAt(utime, {2.0, 5.0, 0.0}));
    replans += navigator.Step(utime).replanned ? 1 : 0;
  }
  EXPECT_EQ(replans, 3);  // at 0.1 s, 1.1 s and 2.1 s
}

TEST(Navigator, StalePoseOrMissingInputsStopTheRobot) {
  Navigator navigator{NavOptions{}};
  navigator.SetGoal(1, {8.0, 5.0}, 0);
  NavOutput out = navigator.Step(kCycleUs);
  EXPECT_EQ(out.status.state, NavState::kActive);
  EXPECT_THAT(out.status.detail, HasSubstr("waiting for a map"));
  navigator.SetMap(Room());
  EXPECT_THAT(navigator.Step(2 * kCycleUs).status.detail, HasSubstr("waiting for a pose"));
  navigator.SetPose(PoseAt(3 * kCycleUs, {2.0, 5.0, 0.0}));
  out = navigator.Step(3 * kCycleUs);
  EXPECT_EQ(out.status.detail, "");
  EXPECT_GT(std::abs(out.command.linear_mps) + std::abs(out.command.angular_radps), 0.0);
  out = navigator.Step(3 * kCycleUs + 600'000);  // no pose for 0.6 s
  EXPECT_THAT(out.status.detail, HasSubstr("pose is stale"));
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_EQ(out.command.angular_radps, 0.0);
}

TEST(Navigator, ScanPointsArePlacedInTheMapWithTheLatestPose) {
  Navigator navigator{NavOptions{}};
  navigator.SetPose(PoseAt(0, {1.0, 2.0, M_PI / 2}));
  LidarScan scan;
  scan.utime = 0;
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = M_PI / 2;
  scan.range_min_m = 0.15;
  scan.range_max_m = 12.0;
  scan.range_m = {1.0, 0.0, 2.0, std::nanf("")};  // beams 1 and 3 have no return
  navigator.SetScan(scan);
  ASSERT_EQ(navigator.scan_points_m().size(), 2u);
  EXPECT_NEAR(navigator.scan_points_m()[0].x_m, 1.0, 1e-9);  // ahead = +y
  EXPECT_NEAR(navigator.scan_points_m()[0].y_m, 3.0, 1e-9);
  EXPECT_NEAR(navigator.scan_points_m()[1].x_m, 1.0, 1e-9);  // behind = -y
  EXPECT_NEAR(navigator.scan_points_m()[1].y_m, 0.0, 1e-9);
}

// A fine sweep from `pose` in a room of `room_size_m` whose walls' inner faces are 0.15 m thick
// (returns 0.05 m inside them, in mapped wall cells), with `points` (obstacles the map does not
// have) as discs of half a cell that shadow the beams behind them.
LidarScan SweepSeeing(const std::vector<Point2d>& points, const Pose2d& pose, int64_t utime,
                      Point2d room_size_m = {10.0, 10.0}) {
  LidarScan scan;
  scan.utime = utime;
  scan.range_min_m = 0.01;
  scan.range_max_m = 100.0;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2 * M_PI / 3600;
  scan.range_m.resize(3600);
  const double low = 0.1, high_x = room_size_m.x_m - 0.1, high_y = room_size_m.y_m - 0.1;
  for (int beam = 0; beam < 3600; ++beam) {
    const double angle = pose.yaw_rad + scan.angle_min_rad + beam * scan.angle_increment_rad;
    const double c = std::cos(angle), s = std::sin(angle);
    double range = 1e9;
    if (c > 1e-9) range = std::min(range, (high_x - pose.x_m) / c);
    if (c < -1e-9) range = std::min(range, (low - pose.x_m) / c);
    if (s > 1e-9) range = std::min(range, (high_y - pose.y_m) / s);
    if (s < -1e-9) range = std::min(range, (low - pose.y_m) / s);
    scan.range_m[beam] = static_cast<float>(range);
  }
  for (const Point2d& p : points) {
    const double dx = p.x_m - pose.x_m, dy = p.y_m - pose.y_m;
    const double distance = std::hypot(dx, dy);
    const double bearing = WrapAngle(std::atan2(dy, dx) - pose.yaw_rad);
    const double half_width = std::asin(std::min(1.0, 0.025 / distance));
    const int first =
        static_cast<int>(std::ceil((bearing - half_width + M_PI) / scan.angle_increment_rad));
    const int last =
        static_cast<int>(std::floor((bearing + half_width + M_PI) / scan.angle_increment_rad));
    for (int b = first; b <= last; ++b) {
      float& range = scan.range_m[(b % 3600 + 3600) % 3600];
      range = std::min(range, static_cast<float>(distance));
    }
  }
  return scan;
}

// Drives with a scan of `obstacle` every cycle, until the goal settles; the closest the robot's
// centre came to the obstacle. `max_y_m` (optional): the farthest north the robot got.
double DriveSeeing(Navigator& navigator, Drive& drive, const std::vector<Point2d>& obstacle,
                   double seconds, double* max_y_m = nullptr, Point2d room_size_m = {10.0, 10.0}) {
  double min_distance_m = 1e9;
  const int64_t end = drive.utime + static_cast<int64_t>(seconds * 1e6);
  while (drive.utime < end) {
    drive.utime += kCycleUs;
    navigator.SetPose(PoseAt(drive.utime, drive.pose));
    navigator.SetScan(SweepSeeing(obstacle, drive.pose, drive.utime, room_size_m));
    const NavOutput out = navigator.Step(drive.utime);
    if (out.status.state != NavState::kActive) break;
    drive.pose = Integrate(drive.pose, out.command, kCycleUs * 1e-6);
    if (max_y_m) *max_y_m = std::max(*max_y_m, drive.pose.y_m);
    for (const Point2d& p : obstacle) {
      min_distance_m =
          std::min(min_distance_m, std::hypot(p.x_m - drive.pose.x_m, p.y_m - drive.pose.y_m));
    }
  }
  return min_distance_m;
}

TEST(Navigator, AnUnmappedObstacleInTheScanIsAvoided) {
  // A scan-only obstacle (a box the map does not have) right on the straight path.
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  Drive drive{{2.0, 5.0, 0.0}};
  navigator.SetGoal(1, {8.0, 5.0}, 0);
  std::vector<Point2d> box;
  for (double y = 4.6; y <= 5.4; y += 0.05) box.push_back({5.0, y});
  const double min_box_distance_m = DriveSeeing(navigator, drive, box, 60.0);
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
  EXPECT_GT(min_box_distance_m, 0.2);
}

// A lidar-made map draws a doorway's jambs a cell thin: the scan returns from the jambs' faces
// one cell into the mapped gap. The planner must see the gap as the DWA does (0.5 m, too narrow
// for a 0.25 m inscribed radius) and take the other door, not drive to the gap and stall there.
TEST(Navigator, ScanReturnsBesideAMappedWallNarrowAGapForThePlannerToo) {
  OccupancyGrid grid = Room();  // its divider drawn here, with a narrower south gap
  for (int row = 0; row < 200; ++row) {
    const bool south_gap = row >= 44 && row <= 55;    // 0.6 m on the map: y 2.2 to 2.8
    const bool north_gap = row >= 140 && row <= 159;  // 1 m: y 7 to 8
    if (south_gap || north_gap) continue;
    for (int col = 99; col < 102; ++col) grid.at({col, row}) = 100;
  }
  std::vector<Point2d> jambs;  // the jambs' faces: returns in gap rows 44 and 55
  for (int col = 99; col < 102; ++col) {
    jambs.push_back(grid.CellCenter({col, 44}));
    jambs.push_back(grid.CellCenter({col, 55}));
  }
  Navigator navigator{LoadNavOptionsFromFile("")};
  navigator.SetMap(grid);
  Drive drive{{3.5, 2.5, 0.0}};
  navigator.SetGoal(1, {7.5, 2.5}, 0);
  double max_y_m = 0.0;
  DriveSeeing(navigator, drive, jambs, 120.0, &max_y_m);
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
  EXPECT_EQ(navigator.status().recoveries_used, 0);
  EXPECT_GT(max_y_m, 7.0);  // through the north door
}

// A chair the map does not hold in the only doorway: the scan's returns shut the way the map
// shows open. They change as the robot moves or the chair does, so the navigator looks again
// (a recovery) instead of calling the goal unreachable at once.
std::vector<Point2d> ChairInTheNorthDoor() {
  std::vector<Point2d> chair;
  for (double y = 6.9; y <= 8.1; y += 0.05) chair.push_back({4.85, y});
  return chair;
}

TEST(Navigator, ScanReturnsShuttingTheOnlyWayAreLookedPastBeforeTheGoalIsGivenUp) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/false));
  Drive drive{{2.5, 7.5, 0.0}};
  navigator.SetGoal(1, {7.5, 7.5}, 0);
  DriveSeeing(navigator, drive, ChairInTheNorthDoor(), 1.0);
  EXPECT_EQ(navigator.status().state, NavState::kActive) << navigator.status().detail;
  EXPECT_NE(navigator.status().recovery, RecoveryPhase::kNone);
  EXPECT_THAT(navigator.status().detail, HasSubstr("scan returns the map does not hold"));
  // It looks around in place: turned, not moved.
  EXPECT_DOUBLE_EQ(drive.pose.x_m, 2.5);
  EXPECT_DOUBLE_EQ(drive.pose.y_m, 7.5);
  EXPECT_GT(std::abs(drive.pose.yaw_rad), 0.3);
  // A new goal behind the same chair, mid-look: a look of its own, still in place.
  navigator.SetGoal(2, {7.5, 7.0}, drive.utime);
  DriveSeeing(navigator, drive, ChairInTheNorthDoor(), 0.5);
  EXPECT_EQ(navigator.status().recovery, RecoveryPhase::kRotate);
  EXPECT_DOUBLE_EQ(drive.pose.x_m, 2.5);
  DriveSeeing(navigator, drive, {}, 120.0);  // the chair is gone
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
}

TEST(Navigator, ScanReturnsThatKeepTheWayShutFailTheGoalAfterTheRecoveries) {
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/false));
  Drive drive{{2.5, 7.5, 0.0}};
  navigator.SetGoal(1, {7.5, 7.5}, 0);
  DriveSeeing(navigator, drive, ChairInTheNorthDoor(), 300.0);
  EXPECT_EQ(navigator.status().state, NavState::kFailed);
  EXPECT_THAT(navigator.status().detail, HasSubstr("scan returns the map does not hold after"));
  EXPECT_EQ(navigator.status().recoveries_used, NavOptions{}.navigator.max_recoveries);
  EXPECT_LT(drive.pose.x_m, 4.6);  // never through the chair

  // A way the map itself shuts is unreachable at once, marks or not.
  OccupancyGrid closed = Room(/*divider=*/true, /*south_gap=*/false);
  for (int row = 0; row < 200; ++row) closed.at({100, row}) = 100;
  navigator.SetMap(closed);
  navigator.SetGoal(2, {7.5, 7.5}, drive.utime);
  DriveSeeing(navigator, drive, ChairInTheNorthDoor(), 1.0);
  EXPECT_EQ(navigator.status().state, NavState::kUnreachable);
  EXPECT_THAT(navigator.status().detail, HasSubstr("no path"));
}

// The livelock of campus runs: a chair the map does not hold shuts the near door, and the way
// round, by a door 25 m off, leads away from it, past the reach of the scan marks. Were the
// marks only the latest scan's, the plan would go back to the near door once the chair fell
// out of their reach (and the planner's goal-distance field was renewed), the robot would turn
// back, see the chair again, and so on. Marks last as long as the goal.
TEST(Navigator, AChairSeenShuttingTheNearDoorKeepsItShutWhenTheRobotTurnsAway) {
  // 10 m x 30 m, 0.15 m walls; a divider at x = 5 m with doors at y 2 to 3 and 27 to 28.
  OccupancyGrid hall(200, 600, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 600; ++row) {
    for (int t = 0; t < 3; ++t) hall.at({t, row}) = hall.at({199 - t, row}) = 100;
    const double y = (row + 0.5) * 0.05;
    if ((y > 2.0 && y < 3.0) || (y > 27.0 && y < 28.0)) continue;
    for (int col = 99; col < 102; ++col) hall.at({col, row}) = 100;
  }
  for (int col = 0; col < 200; ++col) {
    for (int t = 0; t < 3; ++t) hall.at({col, t}) = hall.at({col, 599 - t}) = 100;
  }
  NavOptions options;
  options.navigator.scan_mark_range_m = 1.5;
  Navigator navigator{options};
  navigator.SetMap(hall);
  std::vector<Point2d> chair;  // across the near door
  for (double y = 1.95; y <= 3.05; y += 0.05) chair.push_back({4.85, y});
  Drive drive{{3.5, 2.5, 0.0}};  // 1.35 m from the chair: within the marks' reach
  navigator.SetGoal(1, {7.5, 2.5}, 0);
  double max_y_m = 0.0;
  const double min_chair_distance_m =
      DriveSeeing(navigator, drive, chair, 240.0, &max_y_m, {10.0, 30.0});
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
  EXPECT_EQ(navigator.status().recoveries_used, 0);
  EXPECT_GT(max_y_m, 27.0);  // round by the far door
  EXPECT_GT(min_chair_distance_m, 0.2);
}

// Where the marks come from and go: a return within reach marks its cell while it is within
// reach. One that shut the path ahead stays marked out of reach, for the goal, until a beam
// returns from beyond it, the map holds its cell, or a new goal (or a look) starts from the
// latest scan.
TEST(Navigator, ScanMarksThatShutThePathLastTheGoalUntilSeenThroughOrMapped) {
  Navigator navigator{NavOptions{}};  // marks within 3 m, cleared by returns 0.15 m beyond
  const OccupancyGrid room = Room();
  const std::vector<Point2d> box = {{4.025, 5.025}};  // on the way from (2, 5) to (8, 5)
  const Point2d crate{3.025, 7.025};                  // beside it
  const Point2d wall_face{0.175, 6.025};              // a cell off the west wall's face
  auto marked = [&](const Point2d& p) {
    const Point2d centre = room.CellCenter(room.WorldToCell(p));
    const std::vector<Point2d> marks = navigator.planning_obstacles().points_m;
    return std::any_of(marks.begin(), marks.end(), [&](const Point2d& m) {
      return std::hypot(m.x_m - centre.x_m, m.y_m - centre.y_m) < 1e-6;
    });
  };
  int64_t utime = 0;
  auto look = [&](const Pose2d& pose, const std::vector<Point2d>& seen, const OccupancyGrid& map) {
    utime += kCycleUs;
    navigator.SetPose(PoseAt(utime, pose));
    navigator.SetScan(SweepSeeing(seen, pose, utime));
    navigator.SetMap(map);  // marks the latest scan's returns
    navigator.Step(utime);  // plans when due
  };
  navigator.SetGoal(1, {8.0, 5.0}, 0);
  look({2.0, 5.0, 0.0}, {}, room);  // the straight path
  ASSERT_FALSE(navigator.path_m().empty());
  look({2.0, 5.0, 0.0}, {box[0], crate, wall_face}, room);  // 2 m, 2.2 m and 1.9 m away
  EXPECT_TRUE(marked(box[0]));
  EXPECT_TRUE(marked(crate));
  EXPECT_TRUE(marked(wall_face));
  // All still seen from 4.5 m or more away, out of reach: only the box stays marked.
  look({8.5, 5.0, M_PI}, {box[0], crate, wall_face}, room);
  EXPECT_TRUE(marked(box[0]));
  EXPECT_FALSE(marked(crate));
  EXPECT_FALSE(marked(wall_face));
  // Seen through: the box is gone, beams return from the wall behind it.
  look({8.5, 5.0, M_PI}, {}, room);
  EXPECT_FALSE(marked(box[0]));

  // The map holding the cell drops the mark.
  navigator.SetGoal(2, {8.0, 5.0}, utime);
  look({2.0, 5.0, 0.0}, {}, room);
  look({2.0, 5.0, 0.0}, box, room);
  look({8.5, 5.0, M_PI}, box, room);
  EXPECT_TRUE(marked(box[0]));
  OccupancyGrid mapped = room;
  mapped.at(room.WorldToCell(box[0])) = OccupancyGrid::kOccupied;
  look({8.5, 5.0, M_PI}, box, mapped);
  EXPECT_FALSE(marked(box[0]));
  look({8.5, 5.0, M_PI}, box, room);  // and it does not come back from out of reach
  EXPECT_FALSE(marked(box[0]));

  // A new goal starts from the latest scan's marks.
  navigator.SetGoal(3, {8.0, 5.0}, utime);
  look({2.0, 5.0, 0.0}, {}, room);
  look({2.0, 5.0, 0.0}, box, room);
  look({8.5, 5.0, M_PI}, box, room);
  EXPECT_TRUE(marked(box[0]));
  navigator.SetGoal(4, {8.0, 8.0}, utime);
  look({8.5, 5.0, M_PI}, box, room);
  EXPECT_FALSE(marked(box[0]));
}

// A chair appears in the door the robot is heading for: the way round by the other door is
// taken if the trip (driven + the way round) is not much longer than the goal's first plan
// (nav.detour_factor x that + nav.detour_slack_m), else the goal fails (the utility chooses
// again, with the marks).
NavState DriveIntoADoorAChairShuts(double detour_factor, double detour_slack_m, double* max_y_m,
                                   std::string* detail) {
  NavOptions options;
  options.navigator.detour_factor = detour_factor;
  options.navigator.detour_slack_m = detour_slack_m;
  Navigator navigator{options};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/true));
  Drive drive{{2.0, 2.5, 0.0}};
  navigator.SetGoal(1, {8.0, 2.5}, 0);
  DriveSeeing(navigator, drive, {}, 3.0);
  EXPECT_GT(drive.pose.x_m, 2.5);  // on the way to the south door
  EXPECT_LT(MaxPathY(navigator), 3.5);
  std::vector<Point2d> chair;
  for (double y = 1.975; y <= 3.05; y += 0.05) chair.push_back({4.825, y});
  DriveSeeing(navigator, drive, chair, 120.0, max_y_m);
  *detail = navigator.status().detail;
  return navigator.status().state;
}

TEST(Navigator, AWayScanReturnsShutIsLeftForTheWayRoundUnlessThatIsMuchLonger) {
  double max_y_m = 0.0;
  std::string detail;
  // A first plan of about 6 m through the south door; about 1 m driven and 13 m round by the
  // north one.
  const NavigatorOptions defaults;
  EXPECT_EQ(
      DriveIntoADoorAChairShuts(defaults.detour_factor, defaults.detour_slack_m, &max_y_m, &detail),
      NavState::kReached)
      << detail;
  EXPECT_GT(max_y_m, 7.0);
  max_y_m = 0.0;
  EXPECT_EQ(
      DriveIntoADoorAChairShuts(/*detour_factor=*/2.0, /*detour_slack_m=*/0.0, &max_y_m, &detail),
      NavState::kFailed);
  EXPECT_THAT(detail, HasSubstr("shut the way"));
  EXPECT_LT(max_y_m, 3.5);  // failed where the chair was seen
}

// A doorway the map shows 1 m wide; the scan shows clutter narrowing it to 0.5 m from both
// sides, which the planner does not see (scan_mark_range_m = 0). With the full margin the DWA
// may pass only on the doorway's centre line; after a recovery it squeezes through.
double DriveThroughANarrowedDoor(double squeeze_margin_m, NavState* end_state) {
  NavOptions options;
  options.navigator.scan_mark_range_m = 0.0;
  options.navigator.squeeze_margin_m = squeeze_margin_m;
  Navigator navigator{options};
  navigator.SetMap(Room(/*divider=*/true, /*south_gap=*/false));  // the door: y 7 to 8
  std::vector<Point2d> clutter;  // rows 140-144 and 155-159 of the wall's three columns
  for (int col = 99; col < 102; ++col) {
    for (int row : {140, 141, 142, 143, 144, 155, 156, 157, 158, 159}) {
      clutter.push_back({(col + 0.5) * 0.05, (row + 0.5) * 0.05});
    }
  }
  Drive drive{{2.0, 7.5, 0.0}};
  navigator.SetGoal(1, {8.0, 7.5}, 0);
  const double min_distance_m = DriveSeeing(navigator, drive, clutter, 120.0);
  *end_state = navigator.status().state;
  return min_distance_m;
}

TEST(Navigator, AfterARecoveryTheDwaSqueezesThroughAGapNarrowerThanItsMargin) {
  NavState state = NavState::kActive;
  const double min_distance_m =
      DriveThroughANarrowedDoor(NavOptions{}.navigator.squeeze_margin_m, &state);
  EXPECT_EQ(state, NavState::kReached);
  // The clutter's cell edges, never the robot's body, are as close as it came.
  EXPECT_GT(min_distance_m, NavOptions{}.dwa.robot_radius_m + 0.025);

  // Without the squeeze (the full margin after recoveries too) the goal fails at the door.
  DriveThroughANarrowedDoor(NavOptions{}.dwa.safety_margin_m, &state);
  EXPECT_EQ(state, NavState::kFailed);
}

TEST(Navigator, AGoalANewlySeenObstacleSwallowsIsReachedWhereTheRobotSeesIt) {
  // A frontier target the map shows free, 0.06 m in front of a crate that only the scan shows:
  // the robot cannot stand there, nor within 0.15 m; it stops at a cell that sees the goal.
  Navigator navigator{NavOptions{}};
  navigator.SetMap(Room());
  Drive drive{{2.0, 5.0, 0.0}};
  const Point2d goal{7.975, 5.025};
  navigator.SetGoal(1, goal, 0);
  std::vector<Point2d> crate;
  for (double y = 4.5; y <= 5.5; y += 0.025) crate.push_back({8.035, y});
  const double min_crate_distance_m = DriveSeeing(navigator, drive, crate, 60.0);
  EXPECT_EQ(navigator.status().state, NavState::kReached) << navigator.status().detail;
  EXPECT_GT(min_crate_distance_m, 0.2);
  const double from_goal_m = std::hypot(drive.pose.x_m - goal.x_m, drive.pose.y_m - goal.y_m);
  EXPECT_GT(from_goal_m, 0.15);  // not at the goal: it cannot stand there
  EXPECT_LT(from_goal_m,
            NavOptions{}.navigator.goal_snap_m + NavOptions{}.navigator.goal_tolerance_m);
  EXPECT_LT(drive.pose.x_m, goal.x_m);  // on the goal's side of the crate
}

}  // namespace
}  // namespace aslam
