#pragma once

// aslam-slam-bench: the simulator in-process along a scripted drive, its
// odometry and scans fed straight into Slam (no LCM), every AddScan timed;
// then timing, keyframe ATE against the simulator's truth (and what odometry
// alone would give), loop closures and how well the map agrees with the
// world. Optionally records the simulator's output as an LCM log (the replay
// fixtures, event time = sim time) and writes the map and the trajectory.
//
// The wall clock is read for timing only; Slam sees message time.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "eval/trajectory_metrics.h"

namespace aslam {

struct SlamBenchOptions {
  std::string world_dir;            // world folder (map.yaml + world.yaml), required
  std::string drive_path;           // scripted drive (config/drives/*.yaml), required
  std::string config_path;          // `sim:` and `slam:` sections; empty: built-in defaults
  int64_t seed = -1;                // overrides the config's sim.seed when >= 0
  double duration_s = 0.0;          // simulated seconds to run; 0 = the whole drive
  std::string out_dir;              // map.yaml + map.pgm and trajectory.csv; empty: none
  std::string record_log_path;      // ODOMETRY, LIDAR_SCAN and SIM_TRUTH log; empty: none
  bool run_slam = true;             // false: only record
  double progress_period_s = 60.0;  // simulated seconds between progress lines; 0 = never
};

// Runs the bench, printing its report to stdout and errors to stderr.
// Returns the exit status: 0, 1 on a failure, 2 on invalid options.
int RunSlamBench(const SlamBenchOptions& options);

// Odometry (in "odom", sorted by utime) at each keyframe's time, relative to
// the odometry at the first keyframe that has one: comparable with the
// keyframes, whose first is the identity. Keyframes without odometry within
// 0.1 s are left out.
std::vector<TimedPose> OdometryAtKeyframes(const std::vector<TimedPose>& keyframes,
                                           const std::vector<TimedPose>& odometry);

// trajectory.csv: per keyframe its pose, the true pose relative to the truth
// at the first keyframe with the distance between them, and the odometry as
// OdometryAtKeyframes gives it; fields without data are left empty.
void WriteTrajectoryCsv(const std::vector<TimedPose>& keyframes,
                        const std::vector<TimedPose>& truth, const std::vector<TimedPose>& odometry,
                        std::ostream& csv);

}  // namespace aslam
