// aslam-nav-bench: goal-reaching runs of the navigator in closed loop with
// the simulator, in-process on memq:// (true pose and true map stand in for
// SLAM). The bench itself is eval/nav_bench.h.

#include <gflags/gflags.h>

#include "common/flags.h"
#include "eval/nav_bench.h"

DEFINE_string(world, "worlds/test", "world folder or map_server MAP.yaml");
DEFINE_string(config, "", "config file with a `nav:` section (default: built-in defaults)");
DEFINE_int32(runs, 20, "number of random start/goal pairs");
DEFINE_int64(seed, 1, "seed of the pairs (and, plus the run index, of the simulator)");
DEFINE_double(timeout, 240.0, "simulated seconds before a run counts as failed");
DEFINE_double(min_distance, 3.0, "minimum straight-line start-goal distance, m");
DEFINE_double(clearance, 0.4, "minimum obstacle distance of starts and goals, m");
DEFINE_bool(verbose, true, "print every run");
DEFINE_int32(trace, -1, "run only this pair, printing the loop every --trace_period seconds");
DEFINE_double(trace_period, 0.5, "simulated seconds between trace lines");

int main(int argc, char** argv) {
  aslam::ParseFlags(
      &argc, &argv,
      "aslam-nav-bench [--world DIR] [--runs N] [--seed S] [--timeout S] [--config FILE]");
  aslam::NavBenchOptions options;
  options.world = FLAGS_world;
  options.config_path = FLAGS_config;
  options.runs = FLAGS_runs;
  options.seed = FLAGS_seed;
  options.timeout_s = FLAGS_timeout;
  options.min_distance_m = FLAGS_min_distance;
  options.clearance_m = FLAGS_clearance;
  options.verbose = FLAGS_verbose;
  options.trace_run = FLAGS_trace;
  options.trace_period_s = FLAGS_trace_period;
  return aslam::RunNavBench(options);
}
