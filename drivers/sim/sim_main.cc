// aslam-sim: the simulator process. Loads a world, then publishes
// LIDAR_SCAN, ODOMETRY, SIM_TRUTH and SIM_STATUS while following CMD_VEL (or
// a scripted drive), paced at --rate times real time.

#include <csignal>
#include <cstdio>
#include <sstream>

#include <atomic>
#include <optional>
#include <string>

#include <gflags/gflags.h>

#include "common/flags.h"

#include "common/lcm_util.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/sim_node.h"
#include "common/world_file.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file with a `sim:` section (default: built-in defaults)");
DEFINE_string(world, "", "world folder (map.yaml + world.yaml) or a map_server MAP.yaml");
DEFINE_string(start, "", "start pose X,Y,YAW in the world frame (m, m, rad); default: the world's");
DEFINE_int64(seed, -1, "random seed; overrides the config's sim.seed when >= 0");
DEFINE_double(rate, 1.0, "real-time factor: simulated seconds per wall second; 0 = as fast as possible");
DEFINE_double(duration, 0, "simulated seconds to run; 0 = until Ctrl-C (or the drive ends)");
DEFINE_string(drive, "", "scripted drive file (list of velocity segments) followed instead of CMD_VEL");
DEFINE_double(progress, 5.0, "print a progress line every this many simulated seconds; 0 = never");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

std::optional<Pose2d> ParseStart(const std::string& text) {
  std::istringstream in(text);
  Pose2d pose;
  char c1 = 0, c2 = 0;
  if (!(in >> pose.x_m >> c1 >> pose.y_m >> c2 >> pose.yaw_rad) || c1 != ',' || c2 != ',' ||
      !in.eof()) {
    return std::nullopt;
  }
  return pose;
}

int Run() {
  if (FLAGS_world.empty()) {
    std::fprintf(stderr, "aslam-sim: --world is required (a world folder or a MAP.yaml)\n");
    return 2;
  }
  if (FLAGS_rate < 0 || FLAGS_duration < 0) {
    std::fprintf(stderr, "aslam-sim: --rate and --duration must be >= 0\n");
    return 2;
  }
  try {
    SimulatorOptions options = LoadSimulatorOptionsFromFile(FLAGS_config);
    if (FLAGS_seed >= 0) options.seed = static_cast<uint64_t>(FLAGS_seed);

    const WorldInfo world = LoadWorld(FLAGS_world);
    Pose2d start = world.start;
    if (!FLAGS_start.empty()) {
      const auto parsed = ParseStart(FLAGS_start);
      if (!parsed) {
        std::fprintf(stderr, "aslam-sim: --start '%s': expected X,Y,YAW\n", FLAGS_start.c_str());
        return 2;
      }
      start = *parsed;
    } else if (!world.has_start) {
      std::fprintf(stderr, "aslam-sim: %s has no world.yaml with a start: pass --start X,Y,YAW\n",
                   FLAGS_world.c_str());
      return 2;
    }
    const LoadedMap& map = world.map;

    SimNodeOptions node_options;
    node_options.world_label = FLAGS_world;
    if (!FLAGS_drive.empty()) node_options.drive = LoadScriptedDrive(FLAGS_drive);

    Simulator simulator(map.grid, start, options);
    const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
    const auto lcm = OpenLcm(url);
    SimNode node(*lcm, simulator, std::move(node_options));

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-sim: %s (%dx%d cells at %.2f m), start (%.2f, %.2f, %.2f), seed %llu, on %s\n",
                world.map_yaml_path.c_str(), map.grid.width_cells(), map.grid.height_cells(),
                map.grid.resolution_m(), start.x_m, start.y_m, start.yaw_rad,
                static_cast<unsigned long long>(options.seed), url.c_str());
    std::fflush(stdout);

    RealTimeOptions run_options;
    run_options.real_time_factor = FLAGS_rate;
    run_options.duration_s = FLAGS_duration;
    int64_t seconds = 0;
    run_options.every_second = [&seconds](const SimNode& n) {
      ++seconds;
      if (FLAGS_progress <= 0 || seconds % std::max<int64_t>(1, std::llround(FLAGS_progress)) != 0) {
        return;
      }
      const Simulator& s = n.simulator();
      const Pose2d& truth = s.true_pose();
      const Pose2d& odom = s.odom_pose();
      const SimStatus status = s.status();
      std::printf("t=%6.1f s  pose (%6.2f, %6.2f, %5.2f)  odom (%6.2f, %6.2f, %5.2f)  scans %lld  "
                  "collisions %lld  commands %lld\n",
                  n.utime() * 1e-6, truth.x_m, truth.y_m, truth.yaw_rad, odom.x_m, odom.y_m,
                  odom.yaw_rad, static_cast<long long>(status.scans_published),
                  static_cast<long long>(status.collisions),
                  static_cast<long long>(n.subscriptions().stats("CMD_VEL").received));
      std::fflush(stdout);
    };
    const double simulated_s = RunRealTime(*lcm, node, run_options, g_stop);
    std::printf("aslam-sim: stopped after %.1f simulated s, %lld collisions\n", simulated_s,
                static_cast<long long>(simulator.collisions()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-sim: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
      "aslam-sim --world DIR|MAP.yaml [--start X,Y,YAW] [--config FILE] [--seed N] [--rate R]\n"
      "          [--duration S] [--drive FILE] [--lcm-url URL]");
  return aslam::Run();
}
