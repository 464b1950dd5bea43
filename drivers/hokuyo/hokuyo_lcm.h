#pragma once

// The Hokuyo driver on LCM: scans published on LIDAR_SCAN (sensor_pose: the robot
// section's lidar_mount), and the aslam-hokuyo process (hokuyo_main.cc only parses
// its flags).

#include <atomic>
#include <cstdint>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "common/channels.h"
#include "common/sensor_types.h"

namespace aslam {

class HokuyoPublisher {
 public:
  explicit HokuyoPublisher(lcm::LCM& lcm, std::string channel = channels::kLidarScan);
  // Publishes `scan`; never throws (a failure is counted, the next scan tried).
  bool Publish(const LidarScan& scan) noexcept;
  int64_t published() const { return published_; }
  int64_t failures() const { return failures_; }

 private:
  lcm::LCM& lcm_;
  std::string channel_;
  std::atomic<int64_t> published_{0};
  std::atomic<int64_t> failures_{0};
};

struct HokuyoProcessOptions {
  std::string config_file;  // "": defaults (the `hokuyo:` section otherwise)
  std::string lcm_url;      // "": $LCM_DEFAULT_URL, else udpm with ttl=0
  // Flags override the config when set:
  std::string port;
  int baud = 0;  // 0: the config's
  std::string host;
  int tcp_port = 0;  // 0: the config's
  std::string model;
  double status_period_s = 10.0;  // a status line every this many seconds; 0 = never
};

// Runs until SIGINT/SIGTERM; returns 0 after a clean stop, 1 on a config or LCM
// failure, 2 on bad flags. Device trouble is reported and retried, never fatal.
int RunHokuyoProcess(const HokuyoProcessOptions& options);

}  // namespace aslam
