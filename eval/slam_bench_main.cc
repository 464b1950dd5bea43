// aslam-slam-bench: SLAM along a scripted drive with the simulator in-process
// (no LCM): timing, keyframe ATE, loop closures and map agreement; optionally
// records the replay fixtures. The bench itself is eval/slam_bench.h.

#include <gflags/gflags.h>

#include "common/flags.h"
#include "eval/slam_bench.h"

DEFINE_string(world, "", "world folder (map.yaml + world.yaml)");
DEFINE_string(drive, "", "scripted drive file (config/drives/*.yaml)");
DEFINE_string(config, "",
              "config file with `sim:` and `slam:` sections (default: built-in defaults)");
DEFINE_int64(seed, -1, "simulator seed; overrides the config's sim.seed when >= 0");
DEFINE_double(duration, 0.0, "simulated seconds to run; 0 = the whole drive");
DEFINE_string(out, "", "directory for map.yaml + map.pgm and trajectory.csv (created)");
DEFINE_string(record_log, "",
              "also write ODOMETRY, LIDAR_SCAN and SIM_TRUTH to this LCM log (event time = sim "
              "time)");
DEFINE_bool(slam, true, "run SLAM (--noslam with --record-log only records)");
DEFINE_double(progress, 60.0, "print a progress line every this many simulated seconds; 0 = never");

int main(int argc, char** argv) {
  aslam::ParseFlags(
      &argc, &argv,
      "aslam-slam-bench --world DIR --drive FILE [--config FILE] [--seed N] [--duration S]\n"
      "                 [--out DIR] [--record-log FILE [--noslam]]");
  aslam::SlamBenchOptions options;
  options.world_dir = FLAGS_world;
  options.drive_path = FLAGS_drive;
  options.config_path = FLAGS_config;
  options.seed = FLAGS_seed;
  options.duration_s = FLAGS_duration;
  options.out_dir = FLAGS_out;
  options.record_log_path = FLAGS_record_log;
  options.run_slam = FLAGS_slam;
  options.progress_period_s = FLAGS_progress;
  return aslam::RunSlamBench(options);
}
