// aslam-utility: the goal-selection process. Scores FRONTIERS over SLAM_MAP,
// SLAM_POSE, POSE_GRAPH and NAV_STATUS by fd, ags or ours (config
// `utility.method`); publishes UTILITY_SCORES, EXPLORE_GOAL and EXPLORE_STATUS.
// SIGINT/SIGTERM exit 0.

#include <gflags/gflags.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/flags.h"
#include "common/lcm_util.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `utility:` section (default: built-in defaults)");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

int Run() {
  try {
    const UtilityOptions options = LoadUtilityOptionsFromFile(FLAGS_config);
    const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
    const auto lcm = OpenLcm(url);
    UtilityNode node(*lcm, options);

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-utility: method %s on %s, config %s\n",
                UtilityMethodName(options.selector.method), url.c_str(),
                FLAGS_config.empty() ? "(defaults)" : FLAGS_config.c_str());
    std::fflush(stdout);

    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-utility: LCM receive failed: %s\n", std::strerror(errno));
        return 1;
      }
    }
    std::printf(
        "aslam-utility: stopped; %d decisions, %d goals reached, %d failed, "
        "%lld messages dropped\n",
        node.decisions(), node.goals_reached(), node.goals_failed(),
        static_cast<long long>(node.subscriptions().total_dropped()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-utility: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv, "aslam-utility [--config FILE] [--lcm-url URL]");
  return aslam::Run();
}
