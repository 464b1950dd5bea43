#pragma once

// The aslam-slam process (slam_main.cc only parses its flags): loads the
// `slam:` section, runs a SlamNode on the bus until SIGINT/SIGTERM, writes
// map.yaml + map.pgm and graph.g2o to the output folder on SIGUSR1 and at
// exit, and prints the counters.

#include <string>

namespace aslam {

struct SlamProcessOptions {
  std::string lcm_url;      // "": $LCM_DEFAULT_URL, else udpm with ttl=0
  std::string config_file;  // "": built-in defaults
  std::string out_dir;      // "": nothing is written
};

// Runs the process; returns its exit status: 0 after a clean stop, 1 on a
// failure (bad config, LCM).
int RunSlamProcess(const SlamProcessOptions& options);

}  // namespace aslam
