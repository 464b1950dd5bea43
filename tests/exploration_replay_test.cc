// Replays logs/exploration_fixture.lcmlog (recorded by
// logs/record_exploration_fixture.sh: the whole stack exploring worlds/test in
// one process, nav driving) through a fresh SlamNode on memq: the recorded
// ODOMETRY and LIDAR_SCAN, published in recorded order and each dispatched
// before the next, must reproduce every recorded POSE_GRAPH exactly.

#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "aslam/pose_graph_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"

namespace aslam {
namespace {

const std::string kRoot = ASLAM_SOURCE_DIR;

TEST(ExplorationReplay, SlamReproducesTheRecordedPoseGraphs) {
  lcm::LogFile log(kRoot + "/logs/exploration_fixture.lcmlog", "r");
  ASSERT_TRUE(log.good());
  InProcessHost host;
  const SlamConfig config = LoadSlamConfigFromFile(kRoot + "/config/aslam.yaml");
  SlamNode slam_node(host.lcm(), config.slam, config.node);
  std::vector<pose_graph_t> replayed, recorded;
  Subscriptions capture(host.lcm());
  capture.Add<pose_graph_t>(channels::kPoseGraph, [&](const pose_graph_t& m) {
    replayed.push_back(m);
    return true;
  });
  int scans = 0;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (event->channel == channels::kOdometry || event->channel == channels::kLidarScan) {
      scans += event->channel == channels::kLidarScan;
      host.lcm().publish(event->channel, event->data, event->datalen);
      host.DispatchPending();
    } else if (event->channel == channels::kPoseGraph) {
      pose_graph_t graph{};
      ASSERT_EQ(graph.decode(event->data, 0, event->datalen), event->datalen);
      recorded.push_back(graph);
    }
  }
  EXPECT_EQ(slam_node.subscriptions().total_dropped(), 0);
  // An exploration, not a parked robot: the robot drove and SLAM closed a loop.
  ASSERT_GT(scans, 400);
  ASSERT_FALSE(recorded.empty());
  EXPECT_GE(recorded.back().num_nodes, 50);
  EXPECT_GE(recorded.back().loop_closures_accepted, 1);

  ASSERT_EQ(replayed.size(), recorded.size());
  for (std::size_t i = 0; i < recorded.size(); ++i) {
    const pose_graph_t& a = replayed[i];
    const pose_graph_t& b = recorded[i];
    SCOPED_TRACE("graph revision " + std::to_string(b.revision));
    ASSERT_EQ(a.revision, b.revision);
    ASSERT_EQ(a.num_nodes, b.num_nodes);
    ASSERT_EQ(a.num_edges, b.num_edges);
    EXPECT_EQ(a.loop_closures_accepted, b.loop_closures_accepted);
    EXPECT_EQ(a.loop_closures_rejected, b.loop_closures_rejected);
    for (int n = 0; n < a.num_nodes; ++n) {
      EXPECT_EQ(a.nodes[n].utime, b.nodes[n].utime);
      EXPECT_DOUBLE_EQ(a.nodes[n].pose.x_m, b.nodes[n].pose.x_m);
      EXPECT_DOUBLE_EQ(a.nodes[n].pose.y_m, b.nodes[n].pose.y_m);
      EXPECT_DOUBLE_EQ(a.nodes[n].pose.yaw_rad, b.nodes[n].pose.yaw_rad);
    }
    for (int e = 0; e < a.num_edges; ++e) {
      EXPECT_EQ(a.edges[e].from_id, b.edges[e].from_id);
      EXPECT_EQ(a.edges[e].to_id, b.edges[e].to_id);
      EXPECT_EQ(a.edges[e].kind, b.edges[e].kind);
      for (int k = 0; k < 9; ++k)
        EXPECT_DOUBLE_EQ(a.edges[e].information[k], b.edges[e].information[k]);
    }
  }
}

}  // namespace
}  // namespace aslam
