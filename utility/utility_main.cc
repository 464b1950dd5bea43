// aslam-utility: the goal-selection process. Scores FRONTIERS over SLAM_MAP,
// SLAM_POSE, POSE_GRAPH and NAV_STATUS by fd, ags or ours (config
// `utility.method`); publishes UTILITY_SCORES, EXPLORE_GOAL and EXPLORE_STATUS.
// With --state-file, its counters survive a restart. SIGINT/SIGTERM exit 0
// (utility/utility_process.h).

#include <gflags/gflags.h>

#include "common/flags.h"
#include "utility/utility_process.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `utility:` section (default: built-in defaults)");
DEFINE_string(state_file, "",
              "keep the decisions, goal counters, next goal id and blacklist here, read back "
              "after a restart (default: none)");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-utility [--config FILE] [--lcm-url URL] [--state-file FILE]");
  return aslam::RunUtilityProcess({FLAGS_lcm_url, FLAGS_config, FLAGS_state_file});
}
