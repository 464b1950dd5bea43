#pragma once

// SLAM on LCM: subscribes ODOMETRY and LIDAR_SCAN; on every accepted scan
// publishes SLAM_POSE, POSE_GRAPH when the graph changed, and SLAM_MAP when
// the map changed, at most once per map_period_s of message time but at once
// after a loop closure or re-render; both again after republish_period_s without a
// change. With a journal, every graph change is appended to it after each scan. The same
// node runs in the aslam-slam process and in-process on memq:// (docs/architecture.md §4);
// it never reads the wall clock.

#include <cstdint>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "aslam/lidar_scan_t.hpp"
#include "aslam/odometry_t.hpp"
#include "common/lcm_util.h"
#include "slam/slam.h"
#include "slam/slam_config.h"
#include "slam/slam_journal.h"

namespace aslam {

class SlamNode {
 public:
  // Aborts on invalid options: load them through slam_config.h.
  SlamNode(lcm::LCM& lcm, SlamOptions options, SlamNodeOptions node_options = {});

  // Continues from a journal read back (before any input), then publishes the map, the
  // graph and the pose at once, stamped with the last keyframe's time.
  void Resume(SlamSnapshot snapshot);
  // Appends every later graph change to `journal` (not owned), committed after each scan.
  void set_journal(SlamJournalWriter* journal);

  // Writes `dir`/map.yaml + map.pgm (ROS map_server format) and `dir`/graph.g2o,
  // creating `dir`. Before the first scan there is no map: only the graph is
  // written and false returned. Throws std::runtime_error naming the file on failure.
  bool WriteOutputs(const std::string& dir);

  // Multi-line summary of what came in and what was dropped, by channel and reason.
  std::string CountersReport() const;

  const Slam& slam() const { return slam_; }
  Slam& slam() { return slam_; }
  const Subscriptions& subscriptions() const { return subscriptions_; }
  int64_t poses_published() const { return poses_published_; }
  int64_t graphs_published() const { return graphs_published_; }
  int64_t maps_published() const { return maps_published_; }

 private:
  bool OnOdometry(const odometry_t& msg);
  bool OnScan(const LidarScan& scan);
  void PublishMap(int64_t utime);
  void PublishGraph(int64_t utime);

  lcm::LCM& lcm_;
  Slam slam_;
  SlamNodeOptions node_options_;
  Subscriptions subscriptions_;
  // SLAM_POSE carries the speeds the wheels measure now: the latest accepted odometry's.
  double linear_velocity_mps_ = 0.0;
  double angular_velocity_radps_ = 0.0;
  int64_t published_map_revision_ = -1;
  int64_t last_map_utime_ = 0;
  int64_t last_graph_utime_ = 0;
  SlamJournalWriter* journal_ = nullptr;
  int64_t poses_published_ = 0;
  int64_t graphs_published_ = 0;
  int64_t maps_published_ = 0;
};

}  // namespace aslam
