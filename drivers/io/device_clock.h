#pragma once

// Maps a device's own clock onto the host's monotonic clock from arrival times alone: the
// offset is the smallest (arrival - device time) seen over a sliding window, since a message
// never arrives before it was stamped and the quickest transfers bound the latency from
// below. Reports that offset and the jitter of arrivals around it, and starts over when the
// device clock jumps (a reset).

#include <cstdint>
#include <deque>

namespace aslam {

class DeviceClock {
 public:
  // window_s: how long an observed minimum is kept (the host and device clocks drift apart
  // by some ppm, so an old minimum goes stale); reset_s: a change of (arrival - device time)
  // beyond this is a device clock jump.
  explicit DeviceClock(double window_s = 10.0, double reset_s = 1.0);

  // A device time stamp (µs, already unwrapped by the caller) that arrived at
  // `arrival_utime` (host clock). Returns its host time: never after the arrival, never
  // before the previous one returned.
  int64_t Map(int64_t device_us, int64_t arrival_utime);

  // Forgets everything: the device's clock restarted.
  void Reset();

  bool started() const { return !samples_.empty(); }
  // Host time minus device time, ms (valid once started).
  double offset_ms() const { return offset_us_ * 1e-3; }
  // Standard deviation of arrival - mapped time over the window, ms.
  double jitter_ms() const;
  int resets() const { return resets_; }

 private:
  struct Sample {
    int64_t arrival_utime;
    int64_t lag_us;  // arrival - device time
  };
  double window_us_;
  double reset_us_;
  std::deque<Sample> samples_;  // within the window, in arrival order
  std::deque<Sample> minima_;   // increasing lag_us: the window's minimum at the front
  int64_t offset_us_ = 0;
  int64_t last_mapped_utime_ = INT64_MIN;
  int resets_ = 0;
};

}  // namespace aslam
