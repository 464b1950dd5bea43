#pragma once

// The aslam-slam process (slam_main.cc only parses its flags): loads the
// `slam:` section, resumes from a journal if there is one, runs a SlamNode on
// the bus until SIGINT/SIGTERM, journals the graph as it grows, writes
// map.yaml + map.pgm and graph.g2o to the output folder on SIGUSR1 and at
// exit, and prints the counters.

#include <string>

namespace aslam {

struct SlamProcessOptions {
  std::string lcm_url;      // "": $LCM_DEFAULT_URL, else udpm with ttl=0
  std::string config_file;  // "": built-in defaults
  std::string out_dir;      // "": nothing is written
  // DIR/slam.journal records the graph as it grows; when it exists at start (a restart
  // after a crash), SLAM resumes from it. "": no journal.
  std::string journal_dir;
  // Start from DIR/slam.journal (a finished or stopped run), copied into the journal
  // above first when that does not exist yet. "": start empty.
  std::string resume_dir;
};

// Runs the process; returns its exit status: 0 after a clean stop, 1 on a
// failure (bad config, LCM).
int RunSlamProcess(const SlamProcessOptions& options);

}  // namespace aslam
