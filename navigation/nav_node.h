#pragma once

// The navigator on LCM: subscribes SLAM_POSE, SLAM_MAP, LIDAR_SCAN and
// EXPLORE_GOAL; on every scan runs one control cycle and publishes CMD_VEL
// and NAV_STATUS, and NAV_PATH whenever the path was replanned or cleared;
// NAV_OBSTACLES whenever the scan returns it marks change (before the
// NAV_STATUS of that cycle, so a listener deciding on it has them).
// NAV_STATUS also goes out on every goal message and, without scans, at
// least once per second of pose time. The same node runs in the aslam-nav
// process and in-process on memq:// (docs/architecture.md §4).

#include <cmath>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>

#include "aslam/explore_goal_t.hpp"
#include "aslam/lidar_scan_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/lcm_util.h"
#include "common/stream_clock.h"
#include "common/types_lcm.h"
#include "navigation/nav_config.h"
#include "navigation/navigator.h"

namespace aslam {

class NavNode {
 public:
  NavNode(lcm::LCM& lcm, NavOptions options);

  // Publishes a zero CMD_VEL stamped with the latest input time (on shutdown).
  void PublishStop();

  const Navigator& navigator() const { return navigator_; }
  const Subscriptions& subscriptions() const { return subscriptions_; }
  int64_t commands_published() const { return commands_published_; }
  int64_t latest_utime() const { return latest_utime_; }

 private:
  bool OnPose(const pose_t& msg);
  bool OnMap(MapMessage msg);
  bool OnScan(const LidarScan& scan);
  bool OnGoal(const explore_goal_t& msg);
  void PublishStatus(const NavStatus& status);
  void PublishPathIfChanged(int64_t utime);
  void PublishObstaclesIfChanged();
  void NoteTime(int64_t utime);

  lcm::LCM& lcm_;
  Navigator navigator_;
  Subscriptions subscriptions_;
  int64_t latest_utime_ = 0;
  // Control cycles run on the scans' stamps: a bad stamp must not stall replans or timers.
  StreamClock scan_clock_{std::llround(kDefaultMaxTimeGapS * 1e6), kDefaultResyncMessages};
  int64_t last_status_utime_ = 0;
  int64_t published_path_revision_ = 0;
  int64_t published_marks_revision_ = 0;
  int64_t commands_published_ = 0;
};

}  // namespace aslam
