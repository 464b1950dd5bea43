#include "eval/nav_bench.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/world_file.h"
#include "navigation/costmap.h"
#include "navigation/nav_config.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const OccupancyGrid& TestMap() {
  static const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/test");
  return world.map.grid;
}

TEST(DrawGoalPairs, ClearFarApartPlannedAndSeeded) {
  const NavOptions options;
  const std::vector<GoalPair> pairs = DrawGoalPairs(TestMap(), options, 8, 5, 3.0, 0.4);
  ASSERT_EQ(pairs.size(), 8u);
  const Costmap costmap(TestMap(), options.costmap);
  for (const GoalPair& p : pairs) {
    const Point2d start{p.start.x_m, p.start.y_m};
    EXPECT_GE(std::hypot(start.x_m - p.goal.x_m, start.y_m - p.goal.y_m), 3.0);
    EXPECT_GE(costmap.ObstacleDistanceM(TestMap().WorldToCell(start)), 0.4);
    EXPECT_GE(costmap.ObstacleDistanceM(TestMap().WorldToCell(p.goal)), 0.4);
    // A plan is at least as long as the straight line.
    EXPECT_GE(p.path_length_m, std::hypot(start.x_m - p.goal.x_m, start.y_m - p.goal.y_m) - 0.1);
    EXPECT_LE(std::abs(p.start.yaw_rad), M_PI);
  }
  const std::vector<GoalPair> again = DrawGoalPairs(TestMap(), options, 8, 5, 3.0, 0.4);
  const std::vector<GoalPair> other = DrawGoalPairs(TestMap(), options, 8, 6, 3.0, 0.4);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(again[i].start.x_m, pairs[i].start.x_m);
    EXPECT_EQ(again[i].goal.y_m, pairs[i].goal.y_m);
    EXPECT_EQ(again[i].start.yaw_rad, pairs[i].start.yaw_rad);
  }
  EXPECT_NE(other[0].start.yaw_rad, pairs[0].start.yaw_rad);
}

TEST(DrawGoalPairs, ThrowsWhenNoCellIsClearEnough) {
  // The ring corridor is 1.4 m wide: no cell is 2 m from a wall.
  EXPECT_THROW(DrawGoalPairs(TestMap(), NavOptions{}, 1, 1, 3.0, 2.0), std::runtime_error);
}

GoalRunResult Result(NavState state, double time_s, double driven_m, int64_t collisions,
                     double gap_m) {
  GoalRunResult r;
  r.state = state;
  r.time_s = time_s;
  r.distance_traveled_m = driven_m;
  r.collisions = collisions;
  r.min_clearance_m = gap_m;
  return r;
}

TEST(NavBenchTally, SumsAllRunsAndAveragesReachedOnes) {
  NavBenchTally tally;
  const GoalPair pair{{1.0, 2.0, 0.5}, {4.0, 6.0}, 10.0};
  tally.Add(pair, Result(NavState::kReached, 10.0, 5.0, 0, 0.30));   // 0.5 m/s
  tally.Add(pair, Result(NavState::kReached, 20.0, 16.0, 0, 0.25));  // 0.8 m/s
  tally.Add(pair, Result(NavState::kReached, 40.0, 8.0, 0, 0.40));   // 0.2 m/s
  tally.Add(pair, Result(NavState::kFailed, 100.0, 3.0, 2, 0.05));
  EXPECT_EQ(tally.runs, 4);
  EXPECT_EQ(tally.reached, 3);
  EXPECT_DOUBLE_EQ(tally.simulated_s, 170.0);
  EXPECT_FALSE(tally.all_reached_without_collision());
  const std::string text = FormatTally(tally);
  EXPECT_THAT(text, HasSubstr("success 3/4 (75 %)  runs with a collision 1  collisions 2  "
                              "recoveries 0  smallest robot-wall gap 0.05 m\n"));
  // Mean speed 29 m / 70 s; medians of 0.2/0.5/0.8 m/s and 10/20/40 s; 29 m driven of 30 planned.
  EXPECT_THAT(text, HasSubstr("mean speed 0.414 m/s (driven / time), median 0.500 m/s; "
                              "time to goal mean 23.3 s, median 20.0 s; "
                              "driven / planned length 0.967\n"));
}

TEST(NavBenchTally, NoReachedRunPrintsNoMeansOrMedians) {
  NavBenchTally tally;
  tally.Add(GoalPair{}, Result(NavState::kFailed, 30.0, 1.0, 0, 0.2));
  const std::string text = FormatTally(tally);
  EXPECT_THAT(text, HasSubstr("success 0/1 (0 %)"));
  EXPECT_THAT(text, Not(HasSubstr("reached runs")));
  EXPECT_THAT(text, Not(HasSubstr("median")));
}

TEST(FormatGoalRun, OneLineWithSpeedAndDetail) {
  GoalRunResult r = Result(NavState::kReached, 20.0, 9.0, 1, 0.12);
  r.recoveries_used = 2;
  const GoalPair pair{{1.0, 2.0, 0.5}, {4.0, 6.0}, 10.0};
  EXPECT_EQ(FormatGoalRun(3, pair, r),
            "run   3  (  1.00,   2.00,  0.50) -> (  4.00,   6.00)  plan  10.0 m  reached    "
            "    20.0 s  driven   9.0 m  0.45 m/s  gap 0.12 m  collisions 1  recoveries 2\n");
  r.detail = "stuck";
  r.time_s = 0.0;  // no division by zero
  EXPECT_THAT(FormatGoalRun(3, pair, r), HasSubstr("0.00 m/s"));
  EXPECT_THAT(FormatGoalRun(3, pair, r), HasSubstr("recoveries 2  stuck\n"));
}

}  // namespace
}  // namespace aslam
