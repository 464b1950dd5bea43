#pragma once

// aslam-monitor's view of an LCM bus, like `rostopic hz` for every channel at
// once: message count, rate, bandwidth and type per channel, plus the latest
// simulator status.

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "aslam/sim_status_t.hpp"

namespace aslam {

struct MonitorOptions {
  std::string lcm_url;      // empty: ResolveLcmUrl's default
  double duration_s = 0.0;  // seconds to listen; 0 = until SIGINT or SIGTERM
  double period_s = 1.0;    // seconds between reports
};

// Counts what it hears; knows nothing of LCM but the message layout (an
// 8-byte type fingerprint first), so it can be fed bytes in tests.
class BusMonitor {
 public:
  // One message as heard on `channel`. udpm's start-up probe LCM_SELF_TEST is ignored.
  void OnMessage(const std::string& channel, const uint8_t* data, int size_bytes);

  // The channel table: totals since the start, rates over the last `window_s`
  // (since the previous report, whose window it then clears); `total_s` is
  // the time since the start.
  std::string Report(double window_s, double total_s);

  int64_t total_messages() const;

 private:
  struct ChannelCount {
    std::string type = "?";
    int64_t messages = 0;
    int64_t bytes = 0;
    int64_t window_messages = 0;
    int64_t window_bytes = 0;
  };
  std::map<std::string, ChannelCount> channels_;
  std::optional<sim_status_t> sim_status_;
};

// Listens on the bus and prints a report every period until the duration
// passes or SIGINT/SIGTERM (then a final report). Returns the exit status:
// 0 if any message was heard, 3 if none, 1 if LCM cannot be opened.
int RunMonitor(const MonitorOptions& options);

}  // namespace aslam
