#include "drivers/sim/sim_process.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>

#include "common/lcm_util.h"
#include "common/pose2d.h"
#include "common/world_file.h"
#include "drivers/io/host_clock.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/sim_devices.h"
#include "drivers/sim/sim_node.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

void PrintProgress(const SimNode& node) {
  const Simulator& s = node.simulator();
  const Pose2d& truth = s.true_pose();
  const Pose2d& odom = s.odom_pose();
  const SimStatus status = s.status();
  std::printf(
      "t=%6.1f s  pose (%6.2f, %6.2f, %5.2f)  odom (%6.2f, %6.2f, %5.2f)  scans %lld  "
      "collisions %lld  commands %lld\n",
      node.utime() * 1e-6, truth.x_m, truth.y_m, truth.yaw_rad, odom.x_m, odom.y_m, odom.yaw_rad,
      static_cast<long long>(status.scans_published), static_cast<long long>(status.collisions),
      static_cast<long long>(node.subscriptions().stats("CMD_VEL").received));
  std::fflush(stdout);
}

}  // namespace

int RunSimProcess(const SimProcessOptions& o) {
  if (o.world.empty()) {
    std::fprintf(stderr, "aslam-sim: --world is required (a world folder or a MAP.yaml)\n");
    return 2;
  }
  if (o.real_time_factor < 0 || o.duration_s < 0) {
    std::fprintf(stderr, "aslam-sim: --rate and --duration must be >= 0\n");
    return 2;
  }
  if (!o.devices_dir.empty() && (o.real_time_factor != 1.0 || !o.drive_file.empty())) {
    std::fprintf(stderr,
                 "aslam-sim: --devices runs at real time without a drive: the drivers stamp "
                 "with the host clock and the base follows its driver (got --rate %g%s)\n",
                 o.real_time_factor, o.drive_file.empty() ? "" : " and --drive");
    return 2;
  }
  try {
    SimulatorOptions options = LoadSimulatorOptionsFromFile(o.config_file);
    if (o.seed >= 0) options.seed = static_cast<uint64_t>(o.seed);

    const WorldInfo world = LoadWorld(o.world);
    Pose2d start = world.start;
    if (!o.start.empty()) {
      const auto parsed = ParsePose(o.start);
      if (!parsed) {
        std::fprintf(stderr, "aslam-sim: --start '%s': expected X,Y,YAW\n", o.start.c_str());
        return 2;
      }
      start = *parsed;
    } else if (!world.has_start) {
      std::fprintf(stderr, "aslam-sim: %s has no world.yaml with a start: pass --start X,Y,YAW\n",
                   o.world.c_str());
      return 2;
    }
    const LoadedMap& map = world.map;

    SimNodeOptions node_options;
    node_options.world_label = o.world;
    if (!o.drive_file.empty()) node_options.drive = LoadScriptedDrive(o.drive_file);

    Simulator simulator(map.grid, start, options);
    std::unique_ptr<SimDevices> devices;
    if (!o.devices_dir.empty()) {
      SimDevicesOptions device_options;
      device_options.dir = o.devices_dir;
      device_options.rplidar_model = o.devices_lidar;
      devices = std::make_unique<SimDevices>(simulator, device_options);
      node_options.devices = devices.get();
      std::printf("aslam-sim: devices in the loop: Kobuki on %s, RPLIDAR %s on %s\n",
                  devices->kobuki_port().c_str(), o.devices_lidar.c_str(),
                  devices->rplidar_port().c_str());
    }
    const std::string url = ResolveLcmUrl(o.lcm_url);
    const auto lcm = OpenLcm(url);
    SimNode node(*lcm, simulator, std::move(node_options));
    // Truth on the host's clock where drivers stamp the data; else on simulated time.
    if (devices) node.set_host_clock_offset_us(HostClockUtime() - node.utime());

    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf(
        "aslam-sim: %s (%dx%d cells at %.2f m), start (%.2f, %.2f, %.2f), seed %llu, on %s\n",
        world.map_yaml_path.c_str(), map.grid.width_cells(), map.grid.height_cells(),
        map.grid.resolution_m(), start.x_m, start.y_m, start.yaw_rad,
        static_cast<unsigned long long>(options.seed), url.c_str());
    std::fflush(stdout);

    RealTimeOptions run_options;
    run_options.real_time_factor = o.real_time_factor;
    run_options.duration_s = o.duration_s;
    const int64_t progress_every_s = std::max<int64_t>(1, std::llround(o.progress_period_s));
    int64_t seconds = 0;
    run_options.every_second = [&](const SimNode& n) {
      ++seconds;
      if (o.progress_period_s > 0 && seconds % progress_every_s == 0) PrintProgress(n);
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

}  // namespace aslam
