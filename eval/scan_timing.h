#pragma once

// How far a lidar's time stamps sit from when its beams were measured, judged against the
// simulator's truth: devices in the loop (docs/architecture.md §4) pass the real drivers'
// scans through, and a stamp that is early or late turns every scan taken in a turn. For
// each scan taken while the robot turned, the shift of the stamps that best explains its
// ranges against the true map (ray casts from the true pose); the median over those scans.
// Pure C++, no LCM.

#include <cstdint>
#include <limits>
#include <vector>

#include "common/sensor_types.h"
#include "drivers/sim/sim_world.h"
#include "eval/trajectory_metrics.h"

namespace aslam {

struct ScanTimingOptions {
  double max_shift_ms = 40.0;         // shifts searched: [-max, +max]
  double min_turn_rate_radps = 0.5;   // scans taken turning slower say little about time
  int beam_stride = 2;                // every n-th beam
  double residual_cap_m = 0.3;        // a beam farther off counts this much (clutter, edges)
  int max_scans = 200;                // spread evenly over the run when there are more
  int64_t max_truth_gap_us = 100000;  // truth must lie this close around a beam
};

struct ScanTiming {
  int scans = 0;  // scans taken in turns that were fitted
  // Stamp minus the instant the ranges were measured, ms: > 0 stamps late, < 0 early.
  // NaN when no scan was fitted.
  double median_ms = std::numeric_limits<double>::quiet_NaN();
  double p10_ms = std::numeric_limits<double>::quiet_NaN();
  double p90_ms = std::numeric_limits<double>::quiet_NaN();
};

// `scans` in any order; `truth`: the base's true pose in the world sorted by utime, on the
// scans' clock; `world`: the true map.
ScanTiming EstimateScanTiming(const std::vector<LidarScan>& scans,
                              const std::vector<TimedPose>& truth, const SimWorld& world,
                              const ScanTimingOptions& options = ScanTimingOptions());

}  // namespace aslam
