#include "drivers/io/driver_status.h"

namespace aslam {

void RateCounter::Count(int64_t utime) {
  ++total_;
  if (window_start_utime_ < 0) window_start_utime_ = utime;
  if (utime - window_start_utime_ >= 1000000) {
    last_rate_hz_ = in_window_ * 1e6 / static_cast<double>(utime - window_start_utime_);
    window_start_utime_ = utime;
    in_window_ = 0;
  }
  ++in_window_;
}

double RateCounter::rate_hz(int64_t now_utime) const {
  // Nothing for two seconds: the rate is zero, whatever the last window said.
  if (window_start_utime_ < 0 || now_utime - window_start_utime_ > 2000000) return 0.0;
  return last_rate_hz_;
}

}  // namespace aslam
