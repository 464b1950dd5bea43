// aslam-nav: the navigator process. Follows EXPLORE_GOAL over SLAM_POSE,
// SLAM_MAP and LIDAR_SCAN; publishes CMD_VEL, NAV_STATUS and NAV_PATH.
// SIGINT/SIGTERM publish a zero CMD_VEL and exit 0.

#include <gflags/gflags.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/flags.h"
#include "common/lcm_util.h"
#include "navigation/nav_config.h"
#include "navigation/nav_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `nav:` section (default: built-in defaults)");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

int Run() {
  try {
    const NavOptions options = LoadNavOptionsFromFile(FLAGS_config);
    const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
    const auto lcm = OpenLcm(url);
    NavNode node(*lcm, options);

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-nav: on %s, config %s\n", url.c_str(),
                FLAGS_config.empty() ? "(defaults)" : FLAGS_config.c_str());
    std::fflush(stdout);

    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-nav: LCM receive failed: %s\n", std::strerror(errno));
        node.PublishStop();
        return 1;
      }
    }
    node.PublishStop();
    std::printf("aslam-nav: stopped; %lld commands, %lld messages dropped\n",
                static_cast<long long>(node.commands_published()),
                static_cast<long long>(node.subscriptions().total_dropped()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-nav: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv, "aslam-nav [--config FILE] [--lcm-url URL]");
  return aslam::Run();
}
