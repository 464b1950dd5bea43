// aslam-sim: the simulator process. Loads a world, then publishes
// LIDAR_SCAN, ODOMETRY, SIM_TRUTH and SIM_STATUS while following CMD_VEL (or
// a scripted drive), paced at --rate times real time (drivers/sim/sim_process.h).

#include <gflags/gflags.h>

#include "common/flags.h"
#include "drivers/sim/sim_process.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "",
              "config file with `robot:` and `sim:` sections (default: built-in defaults)");
DEFINE_string(world, "", "world folder (map.yaml + world.yaml) or a map_server MAP.yaml");
DEFINE_string(start, "", "start pose X,Y,YAW in the world frame (m, m, rad); default: the world's");
DEFINE_int64(seed, -1, "random seed; overrides the config's sim.seed when >= 0");
DEFINE_double(rate, 1.0,
              "real-time factor: simulated seconds per wall second; 0 = as fast as possible");
DEFINE_double(duration, 0, "simulated seconds to run; 0 = until Ctrl-C (or the drive ends)");
DEFINE_string(drive, "",
              "scripted drive file (list of velocity segments) followed instead of CMD_VEL");
DEFINE_string(devices, "",
              "devices in the loop: make DIR/kobuki and DIR/rplidar emulated devices for "
              "aslam-kobuki and aslam-rplidar instead of publishing ODOMETRY and LIDAR_SCAN");
DEFINE_string(devices_lidar, "a2", "the RPLIDAR model emulated with --devices: a1, a2, a3, s1, s2");
DEFINE_double(progress, 5.0, "print a progress line every this many simulated seconds; 0 = never");

int main(int argc, char** argv) {
  aslam::ParseFlags(
      &argc, &argv,
      "aslam-sim --world DIR|MAP.yaml [--start X,Y,YAW] [--config FILE] [--seed N] [--rate R]\n"
      "          [--duration S] [--drive FILE] [--lcm-url URL]");
  aslam::SimProcessOptions options;
  options.lcm_url = FLAGS_lcm_url;
  options.config_file = FLAGS_config;
  options.world = FLAGS_world;
  options.start = FLAGS_start;
  options.seed = FLAGS_seed;
  options.real_time_factor = FLAGS_rate;
  options.duration_s = FLAGS_duration;
  options.drive_file = FLAGS_drive;
  options.progress_period_s = FLAGS_progress;
  options.devices_dir = FLAGS_devices;
  options.devices_lidar = FLAGS_devices_lidar;
  return aslam::RunSimProcess(options);
}
