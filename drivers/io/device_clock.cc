#include "drivers/io/device_clock.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace aslam {

DeviceClock::DeviceClock(double window_s, double reset_s)
    : window_us_(window_s * 1e6), reset_us_(reset_s * 1e6) {}

int64_t DeviceClock::Map(int64_t device_us, int64_t arrival_utime) {
  const int64_t lag_us = arrival_utime - device_us;
  if (!samples_.empty() && std::llabs(lag_us - offset_us_) > reset_us_) {
    samples_.clear();
    minima_.clear();
    ++resets_;
  }
  samples_.push_back({arrival_utime, lag_us});
  while (!minima_.empty() && minima_.back().lag_us >= lag_us) minima_.pop_back();
  minima_.push_back({arrival_utime, lag_us});
  while (arrival_utime - samples_.front().arrival_utime > window_us_) samples_.pop_front();
  while (arrival_utime - minima_.front().arrival_utime > window_us_) minima_.pop_front();
  offset_us_ = minima_.front().lag_us;
  const int64_t mapped = std::clamp(device_us + offset_us_,
                                    std::min(last_mapped_utime_ + 1, arrival_utime), arrival_utime);
  last_mapped_utime_ = mapped;
  return mapped;
}

void DeviceClock::Reset() {
  samples_.clear();
  minima_.clear();
  ++resets_;  // last_mapped_utime_ stays: the host's times never go back
}

double DeviceClock::jitter_ms() const {
  if (samples_.size() < 2) return 0.0;
  double sum = 0.0, sum_sq = 0.0;
  for (const Sample& s : samples_) {
    const double residual = static_cast<double>(s.lag_us - offset_us_);
    sum += residual;
    sum_sq += residual * residual;
  }
  const double n = static_cast<double>(samples_.size());
  const double mean = sum / n;
  return std::sqrt(std::max(sum_sq / n - mean * mean, 0.0)) * 1e-3;
}

}  // namespace aslam
