#include "drivers/kobuki/kobuki_lcm.h"

#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "common/channels.h"
#include "common/lcm_util.h"
#include "common/types_lcm.h"
#include "drivers/io/driver_status_lcm.h"
#include "drivers/io/host_clock.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

}  // namespace

base_status_t ToLcm(const KobukiStatus& s) {
  base_status_t msg;
  msg.utime = s.utime;
  msg.device = s.device;
  msg.connected = s.connected;
  msg.bumper = static_cast<int8_t>(s.sensors.bumper);
  msg.wheel_drop = static_cast<int8_t>(s.sensors.wheel_drop);
  msg.cliff = static_cast<int8_t>(s.sensors.cliff);
  msg.buttons = static_cast<int8_t>(s.sensors.buttons);
  msg.charger = static_cast<int8_t>(s.sensors.charger);
  msg.battery_v = s.sensors.battery_dv * 0.1;
  msg.overcurrent = static_cast<int8_t>(s.sensors.overcurrent);
  msg.hazard_stop = s.hazard_stop;
  msg.command_timeout = s.command_timeout;
  msg.commanded_linear_mps = s.commanded.linear_mps;
  msg.commanded_angular_radps = s.commanded.angular_radps;
  msg.hardware_version = s.hardware_version;
  msg.firmware_version = s.firmware_version;
  msg.unique_id = s.unique_id;
  msg.feedback_packets = s.feedback_packets;
  msg.checksum_errors = s.checksum_errors;
  msg.discarded_bytes = s.discarded_bytes;
  msg.reconnects = s.reconnects;
  return msg;
}

int RunKobukiProcess(const KobukiProcessOptions& p) {
  KobukiOptions options;
  try {
    options = LoadKobukiOptionsFromFile(p.config_file);
    if (!p.port.empty()) options.port = p.port;
    if (p.attempts < 0) throw std::invalid_argument("--attempts must be >= 0");
    ValidateKobukiOptions(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-kobuki: %s\n", e.what());
    return 2;
  }
  try {
    const std::string url = ResolveLcmUrl(p.lcm_url);
    const auto lcm = OpenLcm(url);
    std::signal(SIGINT, [](int) { g_stop = true; });
    std::signal(SIGTERM, [](int) { g_stop = true; });
    KobukiDriver driver(options);
    Subscriptions subscriptions(*lcm);
    subscriptions.Add<velocity_command_t>(channels::kCmdVel, [&](const velocity_command_t& msg) {
      const auto command = FromLcm(msg);
      return command && driver.OnCommand(*command, HostClockUtime());
    });
    int64_t next_driver_status_utime = 0;
    KobukiLoopCallbacks callbacks;
    callbacks.service = [&] {
      while (lcm->handleTimeout(0) > 0) {
      }
    };
    callbacks.on_odometry = [&](const Odometry& odometry) {
      const odometry_t msg = ToLcm(odometry);
      lcm->publish(channels::kOdometry, &msg);
    };
    callbacks.on_status = [&](const KobukiStatus& status, const DriverStatus& driver_status) {
      const base_status_t msg = ToLcm(status);
      lcm->publish(channels::kBaseStatus, &msg);
      if (driver_status.utime >= next_driver_status_utime) {
        PublishDriverStatus(*lcm, driver_status);
        next_driver_status_utime = driver_status.utime + 1000000;
      }
    };
    std::printf("aslam-kobuki: %s at %d baud, publishing %s and %s, obeying %s on %s\n",
                options.port.c_str(), kobuki::kBaud, channels::kOdometry, channels::kBaseStatus,
                channels::kCmdVel, url.c_str());
    std::fflush(stdout);
    RunKobukiLoop(driver, options, g_stop, callbacks, {}, p.attempts);
    const KobukiStatus status = driver.status();
    std::printf("aslam-kobuki: stopped after %lld feedback packets (%lld checksum errors)\n",
                static_cast<long long>(status.feedback_packets),
                static_cast<long long>(status.checksum_errors));
    return g_stop ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-kobuki: %s\n", e.what());
    return 1;
  }
}

}  // namespace aslam
