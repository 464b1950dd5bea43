// aslam-frontier: the frontier extraction process. Extracts frontiers from
// every new SLAM_MAP revision seen from SLAM_POSE and publishes FRONTIERS.
// SIGINT/SIGTERM exit 0; a bad config exits 1 naming file, key and value.

#include <gflags/gflags.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/flags.h"
#include "common/lcm_util.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `frontier:` section (default: built-in defaults)");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

int Run() {
  try {
    const FrontierOptions options = LoadFrontierOptionsFromFile(FLAGS_config);
    const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
    const auto lcm = OpenLcm(url);
    FrontierNode node(*lcm, options);

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-frontier: on %s, config %s\n", url.c_str(),
                FLAGS_config.empty() ? "(defaults)" : FLAGS_config.c_str());
    std::fflush(stdout);

    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-frontier: LCM receive failed: %s\n", std::strerror(errno));
        return 1;
      }
    }
    std::printf("aslam-frontier: stopped; %lld frontier lists published, %lld messages dropped\n",
                static_cast<long long>(node.lists_published()),
                static_cast<long long>(node.subscriptions().total_dropped()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-frontier: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv, "aslam-frontier [--config FILE] [--lcm-url URL]");
  return aslam::Run();
}
