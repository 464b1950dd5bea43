#include "drivers/hokuyo/hokuyo_lcm.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "common/channels.h"
#include "common/config.h"
#include "common/lcm_util.h"
#include "common/types_lcm.h"
#include "drivers/hokuyo/hokuyo_driver.h"
#include "drivers/io/driver_status_lcm.h"
#include "drivers/io/host_clock.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

DriverStatus HokuyoDriverStatus(const HokuyoOptions& options, const HokuyoDriver& driver,
                                int64_t published) {
  const HokuyoStats s = driver.stats();
  DriverStatus status;
  status.utime = HostClockUtime();
  status.driver = "aslam-hokuyo";
  status.device = options.device_name();
  status.connected = s.connected;
  status.messages = published;
  status.clock_offset_ms = s.clock_offset_ms;
  status.clock_jitter_ms = s.clock_jitter_ms;
  status.errors = s.checksum_errors + s.scans_dropped + s.error_statuses;
  status.reconnects = static_cast<int>(s.reconnects);
  status.detail = driver.last_error();
  return status;
}

// Applies the flags over the config's options; returns "" or what is wrong with a flag.
std::string ApplyFlags(const HokuyoProcessOptions& flags, HokuyoOptions* o) {
  if (!flags.port.empty()) {
    o->port = flags.port;
    if (flags.host.empty()) o->host.clear();  // a --port beats the config's host
  }
  if (!flags.host.empty()) {
    o->host = flags.host;
    if (flags.port.empty()) o->port.clear();
  }
  if (flags.baud < 0) return "--baud must be > 0";
  if (flags.baud > 0) o->baud = flags.baud;
  if (flags.tcp_port < 0 || flags.tcp_port > 65535) return "--tcp_port must be 1..65535";
  if (flags.tcp_port > 0) o->tcp_port = flags.tcp_port;
  if (!flags.model.empty()) {
    const auto model = ParseHokuyoModel(flags.model);
    if (!model) return "--model '" + flags.model + "': expected auto, urg04lx, ust10lx or ust20lx";
    o->model = *model;
  }
  return "";
}

}  // namespace

HokuyoPublisher::HokuyoPublisher(lcm::LCM& lcm, std::string channel)
    : lcm_(lcm), channel_(std::move(channel)) {}

bool HokuyoPublisher::Publish(const LidarScan& scan) noexcept {
  try {
    const lidar_scan_t msg = ToLcm(scan);
    if (lcm_.publish(channel_, &msg) == 0) {
      ++published_;
      return true;
    }
  } catch (...) {
    // Counted below: a scan lost is better than a driver stopped.
  }
  ++failures_;
  return false;
}

int RunHokuyoProcess(const HokuyoProcessOptions& flags) {
  HokuyoOptions options;
  try {
    options = LoadHokuyoOptionsFromFile(flags.config_file);
    const std::string flag_error = ApplyFlags(flags, &options);
    if (!flag_error.empty()) {
      std::fprintf(stderr, "aslam-hokuyo: %s\n", flag_error.c_str());
      return 2;
    }
    ResolveHokuyoTransport(&options);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "aslam-hokuyo: %s\n", e.what());
    return flags.config_file.empty() ? 2 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-hokuyo: %s\n", e.what());
    return 1;
  }
  std::unique_ptr<lcm::LCM> lcm;
  const std::string url = ResolveLcmUrl(flags.lcm_url);
  try {
    lcm = OpenLcm(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-hokuyo: %s\n", e.what());
    return 1;
  }
  HokuyoPublisher publisher(*lcm, channels::kLidarScan);
  HokuyoDriver driver(options);
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::printf("aslam-hokuyo: %s (%s, model %s), publishing %s on %s\n",
              options.device_name().c_str(), options.uses_tcp() ? "TCP" : "serial",
              HokuyoModelName(options.model).c_str(), channels::kLidarScan, url.c_str());
  std::fflush(stdout);
  std::thread scanning(
      [&] { driver.Run(g_stop, [&](const LidarScan& scan) { publisher.Publish(scan); }); });
  auto next_status = std::chrono::steady_clock::now();
  auto next_driver_status = next_status;
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (std::chrono::steady_clock::now() >= next_driver_status) {
      next_driver_status += std::chrono::seconds(1);
      PublishDriverStatus(*lcm, HokuyoDriverStatus(options, driver, publisher.published()));
    }
    if (flags.status_period_s <= 0 || std::chrono::steady_clock::now() < next_status) continue;
    next_status += std::chrono::milliseconds(static_cast<int>(flags.status_period_s * 1000));
    const HokuyoStats s = driver.stats();
    std::printf(
        "aslam-hokuyo: scans %lld published %lld (failed %lld), dropped %lld, checksum errors "
        "%lld, partial %lld, garbage bytes %lld, error statuses %lld, reconnects %lld\n",
        static_cast<long long>(s.scans), static_cast<long long>(publisher.published()),
        static_cast<long long>(publisher.failures()), static_cast<long long>(s.scans_dropped),
        static_cast<long long>(s.checksum_errors), static_cast<long long>(s.partial_packets),
        static_cast<long long>(s.garbage_bytes), static_cast<long long>(s.error_statuses),
        static_cast<long long>(s.reconnects));
    std::fflush(stdout);
  }
  scanning.join();
  std::printf("aslam-hokuyo: stopped after %lld scans\n",
              static_cast<long long>(driver.stats().scans));
  return 0;
}

}  // namespace aslam
