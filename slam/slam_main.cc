// aslam-slam: the SLAM process. Builds the pose graph and the occupancy grid
// from ODOMETRY and LIDAR_SCAN; publishes SLAM_POSE, POSE_GRAPH and SLAM_MAP.
// With --out-dir, writes map.yaml + map.pgm and graph.g2o there on SIGUSR1
// and at exit. SIGINT/SIGTERM write the outputs, print the counters, exit 0.

#include <gflags/gflags.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "common/flags.h"
#include "common/lcm_util.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `slam:` section (default: built-in defaults)");
DEFINE_string(out_dir, "",
              "folder for map.yaml, map.pgm and graph.g2o, written on SIGUSR1 and at exit "
              "(default: none)");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_save{false};

// Failing to save is reported, not fatal: SLAM keeps running (or exits cleanly).
void Save(SlamNode& node) {
  if (FLAGS_out_dir.empty()) {
    std::printf("aslam-slam: no --out-dir, nothing written\n");
    return;
  }
  try {
    const bool map_written = node.WriteOutputs(FLAGS_out_dir);
    std::printf("aslam-slam: wrote %s/graph.g2o (%zu keyframes)%s\n", FLAGS_out_dir.c_str(),
                node.slam().graph().nodes.size(),
                map_written ? " and map.yaml + map.pgm" : "; no map yet");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: writing outputs failed: %s\n", e.what());
  }
  std::fflush(stdout);
}

int Run() {
  try {
    const SlamConfig config = LoadSlamConfigFromFile(FLAGS_config);
    const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
    const auto lcm = OpenLcm(url);
    SlamNode node(*lcm, config.slam, config.node);

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::signal(SIGUSR1, [](int) { g_save = true; });
    std::printf("aslam-slam: on %s, config %s, outputs %s\n", url.c_str(),
                FLAGS_config.empty() ? "(defaults)" : FLAGS_config.c_str(),
                FLAGS_out_dir.empty() ? "(none)" : FLAGS_out_dir.c_str());
    std::fflush(stdout);

    // The timeout bounds how long a signal waits to be noticed.
    while (!g_stop.load()) {
      // A signal interrupts the wait with an error; only a failure without one is real.
      if (lcm->handleTimeout(100) < 0 && !g_stop.load() && !g_save.load() && errno != EINTR) {
        std::fprintf(stderr, "aslam-slam: LCM receive failed: %s\n", std::strerror(errno));
        Save(node);
        return 1;
      }
      if (g_save.exchange(false)) Save(node);
    }
    Save(node);
    std::printf("aslam-slam: stopped\n%s", node.CountersReport().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-slam: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv, "aslam-slam [--config FILE] [--lcm-url URL] [--out-dir DIR]");
  return aslam::Run();
}
