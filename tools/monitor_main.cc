// aslam-monitor: a text-mode view of an LCM bus, like `rostopic hz` for
// every channel at once: message rate, bandwidth and type per channel, plus
// the latest simulator status. For a GUI with every field, use scripts/spy.

#include <csignal>
#include <cstdio>
#include <cstring>

#include <atomic>
#include <chrono>
#include <map>
#include <optional>
#include <string>

#include <gflags/gflags.h>

#include "common/flags.h"
#include <lcm/lcm-cpp.hpp>

#include "aslam/sim_status_t.hpp"
#include "aslam/type_registry.hpp"
#include "common/lcm_util.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_double(duration, 0, "seconds to listen; 0 = until Ctrl-C");
DEFINE_double(period, 1.0, "seconds between reports");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

struct ChannelCount {
  std::string type = "?";
  int64_t messages = 0;
  int64_t bytes = 0;
  int64_t window_messages = 0;
  int64_t window_bytes = 0;
};

class Monitor {
 public:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    if (channel == "LCM_SELF_TEST") return;  // udpm's own start-up probe
    ChannelCount& count = channels_[channel];
    if (count.type == "?" && rbuf->data_size >= 8) {
      int64_t hash = 0;
      __int64_t_decode_array(rbuf->data, 0, rbuf->data_size, &hash, 1);
      count.type = TypeName(hash);
    }
    ++count.messages;
    ++count.window_messages;
    count.bytes += rbuf->data_size;
    count.window_bytes += rbuf->data_size;
    if (channel == "SIM_STATUS") {
      sim_status_t status{};
      if (status.decode(rbuf->data, 0, rbuf->data_size) > 0) sim_status_ = status;
    }
  }

  void Report(double window_s, double total_s) {
    std::printf("--- %.1f s: %zu channels\n", total_s, channels_.size());
    std::printf("%-16s %-28s %9s %8s %10s\n", "channel", "type", "messages", "Hz", "kB/s");
    for (auto& [name, count] : channels_) {
      std::printf("%-16s %-28s %9lld %8.1f %10.1f\n", name.c_str(), count.type.c_str(),
                  static_cast<long long>(count.messages), count.window_messages / window_s,
                  count.window_bytes / window_s / 1e3);
      count.window_messages = 0;
      count.window_bytes = 0;
    }
    if (sim_status_) {
      std::printf("sim: t=%.1f s  x%.1f real time  collisions=%d  scans=%lld  dropped=%lld\n",
                  sim_status_->utime * 1e-6, sim_status_->real_time_factor,
                  sim_status_->collisions, static_cast<long long>(sim_status_->scans_published),
                  static_cast<long long>(sim_status_->messages_dropped));
    }
    std::fflush(stdout);
  }

  int64_t total_messages() const {
    int64_t total = 0;
    for (const auto& entry : channels_) total += entry.second.messages;
    return total;
  }

 private:
  static std::string TypeName(int64_t hash) {
    for (const auto& [type_hash, name] : TypeRegistry()) {
      if (type_hash == hash) return name;
    }
    return "unknown";
  }

  std::map<std::string, ChannelCount> channels_;
  std::optional<sim_status_t> sim_status_;
};

int Run() {
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
  std::unique_ptr<lcm::LCM> lcm;
  try {
    lcm = OpenLcm(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-monitor: %s\n", e.what());
    return 1;
  }
  Monitor monitor;
  lcm->subscribe(".*", &Monitor::OnMessage, &monitor);
  std::printf("aslam-monitor: listening on %s\n", url.c_str());

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_report = start;
  while (!g_stop) {
    lcm->handleTimeout(50);
    const auto now = Clock::now();
    const double total_s = std::chrono::duration<double>(now - start).count();
    const double window_s = std::chrono::duration<double>(now - last_report).count();
    const bool finished = FLAGS_duration > 0 && total_s >= FLAGS_duration;
    if (window_s >= FLAGS_period || finished) {
      monitor.Report(window_s, total_s);
      last_report = now;
    }
    if (finished) break;
  }
  if (!(FLAGS_duration > 0)) {
    std::printf("final:\n");
    monitor.Report(std::chrono::duration<double>(Clock::now() - last_report).count(),
                   std::chrono::duration<double>(Clock::now() - start).count());
  }
  return monitor.total_messages() > 0 ? 0 : 3;
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
      "aslam-monitor [--lcm-url URL] [--duration S]: message rate and type per channel.\n"
      "Exits 3 if no message was heard.");
  return aslam::Run();
}
