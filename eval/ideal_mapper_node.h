#pragma once

// The ideal explorer's stand-in for aslam-slam (eval/ideal_mapper.h) on LCM: subscribes
// SIM_TRUTH, LIDAR_SCAN and ODOMETRY (for the speeds SLAM_POSE carries), and publishes
// SLAM_POSE on every scan once truth covers it, SLAM_MAP and POSE_GRAPH at most once per map period
// of message time, exactly as SlamNode does, so frontier, utility and navigation run unchanged.

#include <cstdint>
#include <deque>

#include <lcm/lcm-cpp.hpp>

#include "common/lcm_util.h"
#include "eval/ideal_mapper.h"
#include "slam/slam_config.h"

namespace aslam {

class IdealMapperNode {
 public:
  IdealMapperNode(lcm::LCM& lcm, const SlamOptions& slam_options, SlamNodeOptions node_options);

  const IdealMapper& mapper() const { return mapper_; }
  const Subscriptions& subscriptions() const { return subscriptions_; }

 private:
  // Maps the pending scans that truth now covers (all of them when `flush`).
  void MapPendingScans(bool flush);
  void MapScan(const LidarScan& scan);

  lcm::LCM& lcm_;
  IdealMapper mapper_;
  SlamNodeOptions node_options_;
  Subscriptions subscriptions_;
  // Scans wait for the true pose of their last beam: the simulator may publish a scan before the
  // truth of its instant.
  std::deque<LidarScan> pending_scans_;
  double linear_velocity_mps_ = 0.0;
  double angular_velocity_radps_ = 0.0;
  int64_t published_map_revision_ = -1;
  std::size_t published_keyframes_ = 0;
  int64_t last_map_utime_ = 0;
  bool map_published_ = false;
};

}  // namespace aslam
