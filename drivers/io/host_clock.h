#pragma once

// The one host clock every driver stamps its messages with: CLOCK_MONOTONIC in
// microseconds, so a wall-clock step (NTP, a user setting the date) never moves
// a scan against the odometry. Processes on one computer share it.

#include <time.h>

#include <cstdint>

namespace aslam {

inline int64_t HostClockUtime() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<int64_t>(now.tv_sec) * 1000000 + now.tv_nsec / 1000;
}

}  // namespace aslam
