#include "drivers/rplidar/rplidar_lcm.h"

#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "common/channels.h"
#include "common/config.h"
#include "common/lcm_util.h"
#include "common/types_lcm.h"
#include "drivers/io/driver_status_lcm.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

}  // namespace

void PublishLidarScan(lcm::LCM& lcm, const std::string& channel, const LidarScan& scan) {
  const lidar_scan_t msg = ToLcm(scan);
  lcm.publish(channel, &msg);
}

int RunRplidarProcess(const RplidarProcessOptions& p) {
  RplidarOptions options;
  try {
    options = LoadRplidarOptionsFromFile(p.config_file);
    if (!p.port.empty()) options.port = p.port;
    if (p.baud != -1) options.baud = p.baud;
    if (!p.model.empty()) options.model = p.model;
    if (!p.scan_mode.empty()) options.scan_mode = p.scan_mode;
    if (p.attempts < 0) throw std::invalid_argument("--attempts must be >= 0");
    ValidateRplidarOptions(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-rplidar: %s\n", e.what());
    return 2;
  }
  try {
    const std::string url = ResolveLcmUrl(p.lcm_url);
    const auto lcm = OpenLcm(url);
    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    std::printf("aslam-rplidar: %s at %d baud (model %s, scan mode %s), publishing %s on %s\n",
                options.port.c_str(), ResolvedBaud(options), options.model.c_str(),
                options.scan_mode.c_str(), channels::kLidarScan, url.c_str());
    std::fflush(stdout);
    const int64_t published = RunRplidarLoop(
        options, g_stop,
        [&lcm](const LidarScan& scan) { PublishLidarScan(*lcm, channels::kLidarScan, scan); }, {},
        p.attempts, [&lcm](const DriverStatus& status) { PublishDriverStatus(*lcm, status); });
    std::printf("aslam-rplidar: stopped after %lld scans\n", static_cast<long long>(published));
    return g_stop ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-rplidar: %s\n", e.what());
    return 1;
  }
}

}  // namespace aslam
