#pragma once

// The aslam-sim process (sim_main.cc only parses its flags): loads the config
// and the world, then runs a SimNode on the bus paced to the wall clock until
// the duration, the end of a scripted drive, or SIGINT/SIGTERM, printing
// progress to stdout and errors to stderr.

#include <cstdint>
#include <string>

namespace aslam {

struct SimProcessOptions {
  std::string lcm_url;             // "": $LCM_DEFAULT_URL, else udpm with ttl=0
  std::string config_file;         // "": built-in defaults
  std::string world;               // world folder (map.yaml + world.yaml) or a map_server MAP.yaml
  std::string start;               // "X,Y,YAW" in the world frame (m, m, rad); "": the world's
  int64_t seed = -1;               // >= 0 overrides the config's sim.seed
  double real_time_factor = 1.0;   // simulated seconds per wall second; 0 = as fast as possible
  double duration_s = 0.0;         // simulated seconds to run; 0 = until stopped or the drive ends
  std::string drive_file;          // scripted drive followed instead of CMD_VEL; "": none
  double progress_period_s = 5.0;  // simulated seconds between progress lines; 0 = never
  // Devices in the loop (sim_devices.h): DIR/kobuki and DIR/rplidar speak the devices'
  // protocols for the real drivers; "": the simulator publishes ODOMETRY and LIDAR_SCAN.
  std::string devices_dir;
  std::string devices_lidar = "a2";  // the emulated RPLIDAR model
};

// Runs the process; returns its exit status: 0 after a clean stop, 1 on a
// failure (bad config, drive or world file, LCM), 2 on bad arguments.
int RunSimProcess(const SimProcessOptions& options);

}  // namespace aslam
