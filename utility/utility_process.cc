#include "utility/utility_process.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "common/lcm_util.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

}  // namespace

int RunUtilityProcess(const UtilityProcessOptions& process) {
  try {
    const UtilityOptions options = LoadUtilityOptionsFromFile(process.config_file);
    const std::string url = ResolveLcmUrl(process.lcm_url);
    const auto lcm = OpenLcm(url);
    UtilityNode node(*lcm, options);
    if (!process.state_file.empty() && node.UseStateFile(process.state_file)) {
      std::printf("aslam-utility: resuming from %s: %d decisions, %d goals reached, %d failed\n",
                  process.state_file.c_str(), node.decisions(), node.goals_reached(),
                  node.goals_failed());
    }

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-utility: method %s on %s, config %s\n",
                UtilityMethodName(options.selector.method), url.c_str(),
                process.config_file.empty() ? "(defaults)" : process.config_file.c_str());
    std::fflush(stdout);

    bool state_error_reported = false;
    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-utility: LCM receive failed: %s\n", std::strerror(errno));
        return 1;
      }
      if (node.state_file_error() && !state_error_reported) {
        std::fprintf(stderr, "aslam-utility: %s\n", node.state_file_error()->c_str());
        state_error_reported = true;
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

}  // namespace aslam
