#include "tools/monitor.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <memory>

#include <lcm/lcm-cpp.hpp>

#include "aslam/type_registry.hpp"
#include "common/lcm_util.h"
#include "common/text_format.h"

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

std::string TypeName(int64_t fingerprint) {
  for (const auto& [type_fingerprint, name] : TypeRegistry()) {
    if (type_fingerprint == fingerprint) return name;
  }
  return "unknown";
}

}  // namespace

void BusMonitor::OnMessage(const std::string& channel, const uint8_t* data, int size_bytes) {
  if (channel == "LCM_SELF_TEST") return;  // udpm's own start-up probe
  ChannelCount& count = channels_[channel];
  if (count.type == "?" && size_bytes >= 8) {
    int64_t fingerprint = 0;
    __int64_t_decode_array(data, 0, size_bytes, &fingerprint, 1);
    count.type = TypeName(fingerprint);
  }
  ++count.messages;
  ++count.window_messages;
  count.bytes += size_bytes;
  count.window_bytes += size_bytes;
  if (channel == "SIM_STATUS") {
    sim_status_t status{};
    if (status.decode(data, 0, size_bytes) > 0) sim_status_ = status;
  }
}

std::string BusMonitor::Report(double window_s, double total_s) {
  std::string text = Format("--- %.1f s: %zu channels\n", total_s, channels_.size());
  text += Format("%-16s %-28s %9s %8s %10s\n", "channel", "type", "messages", "Hz", "kB/s");
  for (auto& [name, count] : channels_) {
    text += Format("%-16s %-28s %9lld %8.1f %10.1f\n", name.c_str(), count.type.c_str(),
                   static_cast<long long>(count.messages), count.window_messages / window_s,
                   count.window_bytes / window_s / 1e3);
    count.window_messages = 0;
    count.window_bytes = 0;
  }
  if (sim_status_) {
    text += Format("sim: t=%.1f s  x%.1f real time  collisions=%d  scans=%lld  dropped=%lld\n",
                   sim_status_->utime * 1e-6, sim_status_->real_time_factor,
                   sim_status_->collisions, static_cast<long long>(sim_status_->scans_published),
                   static_cast<long long>(sim_status_->messages_dropped));
  }
  return text;
}

int64_t BusMonitor::total_messages() const {
  int64_t total = 0;
  for (const auto& entry : channels_) total += entry.second.messages;
  return total;
}

int RunMonitor(const MonitorOptions& options) {
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  const std::string url = ResolveLcmUrl(options.lcm_url);
  std::unique_ptr<lcm::LCM> lcm;
  try {
    lcm = OpenLcm(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-monitor: %s\n", e.what());
    return 1;
  }
  BusMonitor monitor;
  lcm->subscribeFunction(
      ".*",
      +[](const lcm::ReceiveBuffer* rbuf, const std::string& channel, BusMonitor* m) {
        m->OnMessage(channel, static_cast<const uint8_t*>(rbuf->data),
                     static_cast<int>(rbuf->data_size));
      },
      &monitor);
  std::printf("aslam-monitor: listening on %s\n", url.c_str());

  auto print_report = [&monitor](double window_s, double total_s) {
    std::fputs(monitor.Report(window_s, total_s).c_str(), stdout);
    std::fflush(stdout);
  };
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_report = start;
  while (!g_stop) {
    lcm->handleTimeout(50);
    const auto now = Clock::now();
    const double total_s = std::chrono::duration<double>(now - start).count();
    const double window_s = std::chrono::duration<double>(now - last_report).count();
    const bool finished = options.duration_s > 0 && total_s >= options.duration_s;
    if (window_s >= options.period_s || finished) {
      print_report(window_s, total_s);
      last_report = now;
    }
    if (finished) break;
  }
  if (!(options.duration_s > 0)) {
    std::printf("final:\n");
    print_report(std::chrono::duration<double>(Clock::now() - last_report).count(),
                 std::chrono::duration<double>(Clock::now() - start).count());
  }
  return monitor.total_messages() > 0 ? 0 : 3;
}

}  // namespace aslam
