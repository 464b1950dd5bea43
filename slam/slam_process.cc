#include "slam/slam_process.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "common/lcm_util.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_save{false};

// Failing to save is reported, not fatal: SLAM keeps running (or exits cleanly).
void Save(SlamNode& node, const std::string& out_dir) {
  if (out_dir.empty()) {
    std::printf("aslam-slam: no --out-dir, nothing written\n");
    return;
  }
  try {
    const bool map_written = node.WriteOutputs(out_dir);
    std::printf("aslam-slam: wrote %s/graph.g2o (%zu keyframes)%s\n", out_dir.c_str(),
                node.slam().graph().nodes.size(),
                map_written ? " and map.yaml + map.pgm" : "; no map yet");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: writing outputs failed: %s\n", e.what());
  }
  std::fflush(stdout);
}

}  // namespace

int RunSlamProcess(const SlamProcessOptions& options) {
  try {
    const SlamConfig config = LoadSlamConfigFromFile(options.config_file);
    const std::string url = ResolveLcmUrl(options.lcm_url);
    const auto lcm = OpenLcm(url);
    SlamNode node(*lcm, config.slam, config.node);

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::signal(SIGUSR1, [](int) { g_save = true; });
    std::printf("aslam-slam: on %s, config %s, outputs %s\n", url.c_str(),
                options.config_file.empty() ? "(defaults)" : options.config_file.c_str(),
                options.out_dir.empty() ? "(none)" : options.out_dir.c_str());
    std::fflush(stdout);

    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && !g_save.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-slam: LCM receive failed: %s\n", std::strerror(errno));
        Save(node, options.out_dir);
        return 1;
      }
      if (g_save.exchange(false)) Save(node, options.out_dir);
    }
    Save(node, options.out_dir);
    std::printf("aslam-slam: stopped\n%s", node.CountersReport().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: %s\n", e.what());
    return 1;
  }
}

}  // namespace aslam
