#pragma once

// The aslam-utility process (utility_main.cc only parses its flags): loads the
// `utility:` section, restores the exploration record from the state file when
// there is one, runs a UtilityNode on the bus until SIGINT/SIGTERM and prints
// its counters.

#include <string>

namespace aslam {

struct UtilityProcessOptions {
  std::string lcm_url;      // "": $LCM_DEFAULT_URL, else udpm with ttl=0
  std::string config_file;  // "": built-in defaults
  std::string state_file;   // "": no state kept across restarts
};

// Runs the process; returns its exit status: 0 after a clean stop, 1 on a
// failure (bad config or state file, LCM).
int RunUtilityProcess(const UtilityProcessOptions& options);

}  // namespace aslam
