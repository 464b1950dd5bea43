#pragma once

// A device driver's health and clock, as DRIVER_STATUS carries it (lcmtypes/driver_status_t).

#include <cstdint>
#include <string>

namespace aslam {

struct DriverStatus {
  int64_t utime = 0;  // host monotonic clock
  std::string driver;
  std::string device;
  bool connected = false;
  int64_t messages = 0;
  double rate_hz = 0.0;
  double clock_offset_ms = 0.0;
  double clock_jitter_ms = 0.0;
  int64_t errors = 0;
  int reconnects = 0;
  std::string detail;
};

// Counts what a driver publishes and gives its rate over the last whole second.
class RateCounter {
 public:
  void Count(int64_t utime);
  int64_t total() const { return total_; }
  double rate_hz(int64_t now_utime) const;

 private:
  int64_t total_ = 0;
  int64_t window_start_utime_ = -1;
  int64_t in_window_ = 0;
  double last_rate_hz_ = 0.0;
};

}  // namespace aslam
