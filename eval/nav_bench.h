#pragma once

// aslam-nav-bench: goal-reaching runs of the navigator in closed loop with
// the simulator (eval/nav_closed_loop.h: true pose and true map stand in for
// SLAM). Seeded random start/goal pairs in a world; each run and the success
// rate, collisions, mean speed and time to goal.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "eval/nav_closed_loop.h"
#include "navigation/nav_config.h"

namespace aslam {

struct NavBenchOptions {
  std::string world = "worlds/test";  // world folder or map_server MAP.yaml
  std::string config_path;            // a `nav:` section; empty: built-in defaults
  int runs = 20;                      // random start/goal pairs
  int64_t seed = 1;                   // of the pairs; plus the run index, of the simulator
  double timeout_s = 240.0;           // simulated seconds before a run counts as failed
  double min_distance_m = 3.0;        // straight-line start-goal distance
  double clearance_m = 0.4;           // obstacle distance of starts and goals
  bool verbose = true;                // print every run
  int trace_run = -1;                 // >= 0: run only this pair, printing the loop
  double trace_period_s = 0.5;        // simulated seconds between trace lines
};

// Runs the bench, printing to stdout (errors to stderr). Returns the exit
// status: 0 if every goal was reached without a collision, 3 if not, 1 on a failure.
int RunNavBench(const NavBenchOptions& options);

struct GoalPair {
  Pose2d start;
  Point2d goal;
  double path_length_m = 0.0;  // of the global planner's path
};

// `count` pairs of free cells at least `clearance_m` from an obstacle, at
// least `min_distance_m` apart and connected by a global plan; random start
// heading. The same seed draws the same pairs. Throws std::runtime_error if
// no cell qualifies or too few pairs are found.
std::vector<GoalPair> DrawGoalPairs(const OccupancyGrid& map, const NavOptions& nav_options,
                                    int count, uint64_t seed, double min_distance_m,
                                    double clearance_m);

// One line of the per-run table (with its newline).
std::string FormatGoalRun(std::size_t index, const GoalPair& pair, const GoalRunResult& result);

// The results of all runs.
struct NavBenchTally {
  int runs = 0;
  int reached = 0;
  int runs_with_collision = 0;
  int64_t collisions = 0;
  int recoveries = 0;
  double min_gap_m = std::numeric_limits<double>::infinity();
  double simulated_s = 0.0;
  // Over the reached runs only: sums, and per run for the medians.
  double reached_time_s = 0.0;
  double reached_distance_m = 0.0;
  double reached_path_m = 0.0;
  std::vector<double> reached_times_s;
  std::vector<double> reached_speeds_mps;

  void Add(const GoalPair& pair, const GoalRunResult& result);
  bool all_reached_without_collision() const { return reached == runs && collisions == 0; }
};

// The summary lines: success, collisions and gaps; then speed, time to goal
// and path ratio of the reached runs, a line left out when none was reached.
std::string FormatTally(const NavBenchTally& tally);

}  // namespace aslam
