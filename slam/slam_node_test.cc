#include "slam/slam_node.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "aslam/compressed_occupancy_grid_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/map_io.h"
#include "common/test_temp_dir.h"
#include "common/types_lcm.h"
#include "common/world_file.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_node.h"
#include "slam/g2o_io.h"
#include "slam/slam_journal.h"

namespace aslam {
namespace {

const std::string kRoot = ASLAM_SOURCE_DIR;

const WorldInfo& TestWorld() {
  static const WorldInfo world = LoadWorld(kRoot + "/worlds/test");
  return world;
}

int64_t Dropped(const Slam& slam, DropReason reason) {
  return slam.counters().dropped[static_cast<int>(reason)];
}

// Every loop closure then corrects the map, so it must be published at once.
SlamOptions EveryClosureReRenders() {
  SlamOptions options;
  options.loop_closure.map_rerender_tolerance_m = 0.0;
  return options;
}

// The simulator driving worlds/test's loop and a SlamNode on one memq bus,
// with every message either publishes recorded.
class Harness {
 public:
  Harness()
      : simulator_(TestWorld().map.grid, TestWorld().start, SimulatorOptions{}),
        sim_node_(host_.lcm(), simulator_,
                  {"test", LoadScriptedDrive(kRoot + "/config/drives/test_loop.yaml")}),
        slam_node_(host_.lcm(), EveryClosureReRenders(), SlamNodeOptions{}),
        listener_(host_.lcm()) {
    listener_.Add<lidar_scan_t>(channels::kLidarScan, [this](const lidar_scan_t& m) {
      scans.push_back(m);
      return true;
    });
    listener_.Add<odometry_t>(channels::kOdometry, [this](const odometry_t& m) {
      odometry.push_back(m);
      return true;
    });
    listener_.Add<pose_t>(channels::kSimTruth, [this](const pose_t& m) {
      truth.push_back(m);
      return true;
    });
    listener_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) {
      poses.push_back(m);
      return true;
    });
    listener_.Add<pose_graph_t>(channels::kPoseGraph, [this](const pose_graph_t& m) {
      graphs.push_back(m);
      return true;
    });
    listener_.Add<compressed_occupancy_grid_t>(channels::kSlamMap,
                                               [this](const compressed_occupancy_grid_t& m) {
                                                 maps.push_back(m);
                                                 return true;
                                               });
  }

  void RunFor(double seconds) {
    const int64_t end = sim_node_.utime() + static_cast<int64_t>(seconds * 1e6);
    host_.Run([&] {
      if (sim_node_.utime() >= end) return false;
      sim_node_.Tick();
      return true;
    });
  }

  template <typename Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    host_.lcm().publish(channel, &msg);
    host_.DispatchPending();
  }
  void PublishBytes(const std::string& channel, const std::vector<uint8_t>& bytes) {
    host_.lcm().publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
    host_.DispatchPending();
  }

  const SlamNode& node() const { return slam_node_; }
  SlamNode& mutable_node() { return slam_node_; }
  const Subscriptions& listener() const { return listener_; }

  std::vector<lidar_scan_t> scans;
  std::vector<odometry_t> odometry;
  std::vector<pose_t> truth;
  std::vector<pose_t> poses;
  std::vector<pose_graph_t> graphs;
  std::vector<compressed_occupancy_grid_t> maps;

 private:
  InProcessHost host_;
  Simulator simulator_;
  SimNode sim_node_;
  SlamNode slam_node_;
  Subscriptions listener_;
};

// One lap of the ring (the whole test_loop drive, 108.6 s) shared by the tests
// that only read what was published.
constexpr double kLapS = 110.0;
constexpr std::size_t kLapScans = 1100;

class SlamNodeDrive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    harness_ = new Harness();
    harness_->RunFor(kLapS);
  }
  static void TearDownTestSuite() {
    delete harness_;
    harness_ = nullptr;
  }
  static Harness* harness_;
};
Harness* SlamNodeDrive::harness_ = nullptr;

TEST_F(SlamNodeDrive, PublishesAPoseInMapForEveryScan) {
  const Harness& h = *harness_;
  ASSERT_EQ(h.scans.size(), kLapScans);
  ASSERT_EQ(h.poses.size(), h.scans.size());
  for (std::size_t i = 0; i < h.poses.size(); ++i) {
    EXPECT_EQ(h.poses[i].frame, "map");
    EXPECT_EQ(h.poses[i].utime, h.scans[i].utime);
  }
  // Velocities are the wheels' (the latest odometry at the scan's time).
  EXPECT_EQ(h.poses.back().linear_velocity_mps, h.odometry.back().linear_velocity_mps);
  // A covariance is attached: positive variances, symmetric.
  const pose_t& last = h.poses.back();
  EXPECT_GT(last.covariance[0], 0.0);
  EXPECT_GT(last.covariance[4], 0.0);
  EXPECT_GT(last.covariance[8], 0.0);
  EXPECT_EQ(last.covariance[1], last.covariance[3]);
  // "map" is anchored at the first keyframe, where the robot started: the
  // estimate follows the truth relative to the start (loosely; accuracy is slam_test's).
  const Pose2d start = TestWorld().start;
  const Pose2d truth_in_map = start.Between(FromLcm(h.truth.back().pose));
  EXPECT_EQ(h.truth.back().utime, last.utime);
  EXPECT_NEAR(last.pose.x_m, truth_in_map.x_m, 0.3);
  EXPECT_NEAR(last.pose.y_m, truth_in_map.y_m, 0.3);
  EXPECT_EQ(h.node().poses_published(), static_cast<int64_t>(kLapScans));
  EXPECT_EQ(h.node().subscriptions().total_dropped(), 0);
  EXPECT_EQ(h.node().slam().counters().dropped_total(), 0);
}

TEST_F(SlamNodeDrive, PublishesTheGraphAfterEveryChangeWithIncreasingRevisions) {
  const Harness& h = *harness_;
  ASSERT_GE(h.graphs.size(), 100u);  // ~40 m of travel at a keyframe per 0.3 m
  for (std::size_t i = 1; i < h.graphs.size(); ++i) {
    EXPECT_GT(h.graphs[i].revision, h.graphs[i - 1].revision);
    EXPECT_GE(h.graphs[i].num_nodes, h.graphs[i - 1].num_nodes);
    EXPECT_GE(h.graphs[i].utime, h.graphs[i - 1].utime);
  }
  const pose_graph_t& last = h.graphs.back();
  const Slam& slam = h.node().slam();
  EXPECT_EQ(last.revision, slam.graph_revision());
  EXPECT_EQ(last.loop_closures_accepted, slam.counters().loop_closures_accepted);
  EXPECT_EQ(last.loop_closures_rejected, slam.counters().loop_closures_rejected);
  const auto graph = FromLcm(last);  // valid for any subscriber
  ASSERT_TRUE(graph.has_value());
  EXPECT_EQ(graph->nodes.size(), slam.graph().nodes.size());
  EXPECT_EQ(graph->edges.size(), slam.graph().edges.size());
  EXPECT_EQ(graph->nodes.back().pose.x_m, slam.graph().nodes.back().pose.x_m);
  EXPECT_EQ(h.node().graphs_published(), static_cast<int64_t>(h.graphs.size()));
}

TEST_F(SlamNodeDrive, PublishesTheMapAtMostOncePerSecondOfMessageTimeAndAfterClosures) {
  const Harness& h = *harness_;
  // Loop closures add a map at once; note when they happened.
  std::vector<int64_t> closure_utimes;
  for (std::size_t i = 1; i < h.graphs.size(); ++i) {
    if (h.graphs[i].loop_closures_accepted > h.graphs[i - 1].loop_closures_accepted) {
      closure_utimes.push_back(h.graphs[i].utime);
    }
  }
  ASSERT_FALSE(closure_utimes.empty()) << "the lap closes the loop";
  for (const int64_t utime : closure_utimes) {
    EXPECT_TRUE(
        std::any_of(h.maps.begin(), h.maps.end(),
                    [utime](const compressed_occupancy_grid_t& m) { return m.utime == utime; }))
        << "no SLAM_MAP right after the loop closure at " << utime;
  }
  ASSERT_GE(h.maps.size(), 60u);  // the map changes all along the lap
  ASSERT_LE(h.maps.size(), static_cast<std::size_t>(kLapS) + 1 + closure_utimes.size());
  EXPECT_EQ(h.maps.front().utime, h.scans.front().utime);  // the first at once
  const auto after_closure = [&](int64_t utime) {
    return std::find(closure_utimes.begin(), closure_utimes.end(), utime) != closure_utimes.end();
  };
  for (std::size_t i = 0; i < h.maps.size(); ++i) {
    EXPECT_EQ(h.maps[i].frame, "map");
    EXPECT_TRUE(FromLcm(h.maps[i]).has_value());
    if (i == 0) continue;
    EXPECT_GT(h.maps[i].revision, h.maps[i - 1].revision);
    if (!after_closure(h.maps[i].utime)) {
      EXPECT_GE(h.maps[i].utime - h.maps[i - 1].utime, 1'000'000) << "map " << i;
    }
  }
  // A change not yet published is held back by the period only.
  EXPECT_LE(h.maps.back().revision, h.node().slam().map_revision());
  if (h.maps.back().revision < h.node().slam().map_revision()) {
    EXPECT_LT(h.scans.back().utime - h.maps.back().utime, 1'000'000);
  }
  EXPECT_EQ(h.node().maps_published(), static_cast<int64_t>(h.maps.size()));
}

TEST_F(SlamNodeDrive, WriteOutputsWritesALoadableMapAndTheGraph) {
  SlamNode& node = harness_->mutable_node();
  const std::string dir = TestTempPath("run");
  ASSERT_TRUE(node.WriteOutputs(dir));

  const LoadedMap loaded = LoadMap(dir + "/map.yaml");
  const OccupancyGrid rendered = node.slam().RenderMap();
  EXPECT_EQ(loaded.grid.width_cells(), rendered.width_cells());
  EXPECT_EQ(loaded.grid.height_cells(), rendered.height_cells());
  EXPECT_NEAR(loaded.grid.origin_m().x_m, rendered.origin_m().x_m, 1e-6);
  EXPECT_NEAR(loaded.grid.origin_m().y_m, rendered.origin_m().y_m, 1e-6);
  EXPECT_DOUBLE_EQ(loaded.metadata.resolution_m, 0.05);
  const auto counts = loaded.grid.CountCells();
  EXPECT_GT(counts.free, 1000u);
  EXPECT_GT(counts.occupied, 100u);

  const PoseGraph graph = ReadG2o(dir + "/graph.g2o");
  EXPECT_EQ(graph.nodes.size(), node.slam().graph().nodes.size());
  EXPECT_EQ(graph.edges.size(), node.slam().graph().edges.size());
  std::filesystem::remove_all(dir);
}

// Counts what a node publishes on a memq bus.
struct Published {
  explicit Published(lcm::LCM& lcm) : listener(lcm) {
    listener.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) {
      poses.push_back(m);
      return true;
    });
    listener.Add<pose_graph_t>(channels::kPoseGraph, [this](const pose_graph_t& m) {
      graphs.push_back(m);
      return true;
    });
    listener.Add<compressed_occupancy_grid_t>(channels::kSlamMap,
                                              [this](const compressed_occupancy_grid_t& m) {
                                                maps.push_back(m);
                                                return true;
                                              });
  }
  Subscriptions listener;
  std::vector<pose_t> poses;
  std::vector<pose_graph_t> graphs;
  std::vector<compressed_occupancy_grid_t> maps;
};

// The simulator's odometry and scans of a robot that never moves, until `end_utime`.
void PlayParkedRobot(InProcessHost& host, int64_t end_utime) {
  Simulator sim(TestWorld().map.grid, TestWorld().start, SimulatorOptions{});
  while (sim.utime() < end_utime) {
    const SimStepOutput out = sim.Step();
    if (out.odometry) {
      const odometry_t msg = ToLcm(*out.odometry);
      host.lcm().publish(channels::kOdometry, &msg);
    }
    if (out.scan) {
      const lidar_scan_t msg = ToLcm(*out.scan);
      host.lcm().publish(channels::kLidarScan, &msg);
    }
    host.DispatchPending();
  }
}

TEST(SlamNode, AParkedRobotsMapAndGraphAreRepublished) {
  InProcessHost host;
  SlamNodeOptions node_options;
  SlamNode node(host.lcm(), SlamOptions{}, node_options);
  Published published(host.lcm());
  // 12 s parked: nothing changes after the first keyframe.
  PlayParkedRobot(host, 12'000'000);
  ASSERT_EQ(node.slam().graph().nodes.size(), 1u);
  // The first map, then one per republish period: a node that joins late gets them.
  const int64_t period_us = static_cast<int64_t>(node_options.republish_period_s * 1e6);
  ASSERT_EQ(published.maps.size(), 3u);
  EXPECT_EQ(published.maps[1].utime - published.maps[0].utime, period_us);
  EXPECT_EQ(published.maps[2].utime - published.maps[1].utime, period_us);
  EXPECT_EQ(published.maps[2].revision, published.maps[0].revision);
  EXPECT_EQ(published.graphs.size(), 3u);
}

TEST(SlamNode, AResumedNodeAnnouncesItsMapGraphAndPoseAtOnce) {
  const std::string dir = FreshTestTempDir("resume");
  const std::string path = dir + "/slam.journal";
  std::size_t keyframes = 0;
  {
    Harness h;
    SlamJournalWriter writer(path, 0);
    h.mutable_node().set_journal(&writer);
    h.RunFor(30.0);
    keyframes = h.node().slam().graph().nodes.size();
    h.mutable_node().set_journal(nullptr);
    ASSERT_FALSE(writer.error());
  }
  InProcessHost host;
  SlamNode node(host.lcm(), EveryClosureReRenders(), SlamNodeOptions{});
  Published published(host.lcm());
  node.Resume(ReadSlamJournal(path).snapshot);
  host.DispatchPending();
  ASSERT_EQ(published.poses.size(), 1u);
  ASSERT_EQ(published.graphs.size(), 1u);
  ASSERT_EQ(published.maps.size(), 1u);
  EXPECT_GT(keyframes, 20u);
  EXPECT_EQ(published.graphs[0].num_nodes, static_cast<int>(keyframes));
  EXPECT_EQ(published.poses[0].frame, "map");
  EXPECT_EQ(published.poses[0].utime, published.graphs[0].utime);
  EXPECT_GT(published.maps[0].width_cells * published.maps[0].height_cells, 1000);
  std::filesystem::remove_all(dir);
}

// map_encoding raw: the legacy wire type, for a bus that loses nothing (the in-process runner).
TEST(SlamNode, RawMapEncodingPublishesTheUncompressedGrid) {
  InProcessHost host;
  SlamNodeOptions node_options;
  node_options.map_encoding = SlamNodeOptions::MapEncoding::kRaw;
  SlamNode node(host.lcm(), SlamOptions{}, node_options);
  Subscriptions listener(host.lcm());
  std::vector<MapMessage> raw_maps;
  listener.Add<occupancy_grid_t>(channels::kSlamMap, [&](const occupancy_grid_t& m) {
    auto map = MapFrameGridFromLcm(m);
    if (map) raw_maps.push_back(std::move(*map));
    return map.has_value();
  });
  PlayParkedRobot(host, 2'000'000);
  ASSERT_EQ(raw_maps.size(), 1u);
  EXPECT_EQ(listener.stats(channels::kSlamMap).decode_failures, 0);
  EXPECT_EQ(raw_maps[0].grid.cells(), node.slam().RenderMap().cells());
}

TEST(SlamNode, WriteOutputsBeforeAnyScanWritesOnlyTheGraph) {
  InProcessHost host;
  SlamNode node(host.lcm(), SlamOptions{});
  const std::string dir = TestTempPath("empty");
  EXPECT_FALSE(node.WriteOutputs(dir));
  EXPECT_TRUE(std::filesystem::exists(dir + "/graph.g2o"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/map.yaml"));
  EXPECT_TRUE(ReadG2o(dir + "/graph.g2o").nodes.empty());
  std::filesystem::remove_all(dir);
}

TEST(SlamNode, UndecodableMessagesAreCountedAsDecodeFailures) {
  Harness h;
  h.RunFor(1.0);
  const int64_t scans_before = h.node().slam().counters().scans_received;
  h.PublishBytes(channels::kLidarScan, {1, 2, 3});
  h.PublishBytes(channels::kOdometry, {0xde, 0xad});
  EXPECT_EQ(h.node().subscriptions().stats(channels::kLidarScan).decode_failures, 1);
  EXPECT_EQ(h.node().subscriptions().stats(channels::kOdometry).decode_failures, 1);
  EXPECT_EQ(h.node().subscriptions().total_dropped(), 2);
  EXPECT_EQ(h.node().slam().counters().scans_received, scans_before);
  h.RunFor(1.0);  // and the node carries on
  EXPECT_EQ(h.poses.size(), h.scans.size());
}

TEST(SlamNode, BadInputIsDroppedCountedAndNotPublished) {
  Harness h;
  // A scan before any odometry.
  h.RunFor(0.05);  // odometry at 20 and 40 ms, no scan yet
  {
    InProcessHost fresh_host;
    SlamNode fresh(fresh_host.lcm(), SlamOptions{});
    lidar_scan_t scan{};
    scan.utime = 100000;
    scan.angle_increment_rad = 0.01f;
    scan.range_min_m = 0.15f;
    scan.range_max_m = 12.0f;
    scan.num_ranges = 720;
    scan.range_m.assign(720, 2.0f);
    fresh_host.lcm().publish(channels::kLidarScan, &scan);
    fresh_host.DispatchPending();
    EXPECT_EQ(fresh.subscriptions().stats(channels::kLidarScan).rejected, 1);
    EXPECT_EQ(Dropped(fresh.slam(), DropReason::kScanBeforeOdometry), 1);
  }

  h.RunFor(2.0);
  ASSERT_FALSE(h.scans.empty());
  const std::size_t poses_before = h.poses.size();
  const lidar_scan_t good = h.scans.back();
  const odometry_t last_odometry = h.odometry.back();

  lidar_scan_t all_nan = good;
  all_nan.utime += 1;
  all_nan.range_m.assign(all_nan.range_m.size(), std::numeric_limits<float>::quiet_NaN());
  h.Publish(channels::kLidarScan, all_nan);

  lidar_scan_t sparse = good;
  sparse.utime += 2;
  for (std::size_t i = 10; i < sparse.range_m.size(); ++i) sparse.range_m[i] = 0.0f;
  h.Publish(channels::kLidarScan, sparse);

  lidar_scan_t backwards = good;
  backwards.utime -= 150000;
  h.Publish(channels::kLidarScan, backwards);

  lidar_scan_t malformed = good;  // caught by the translator, before SLAM
  malformed.utime += 3;
  malformed.range_max_m = 0.1f;
  h.Publish(channels::kLidarScan, malformed);

  odometry_t old_odometry = last_odometry;
  old_odometry.utime -= 10000;
  h.Publish(channels::kOdometry, old_odometry);

  const Slam& slam = h.node().slam();
  EXPECT_EQ(h.node().subscriptions().stats(channels::kLidarScan).rejected, 4);
  EXPECT_EQ(h.node().subscriptions().stats(channels::kOdometry).rejected, 1);
  EXPECT_EQ(Dropped(slam, DropReason::kScanTooFewPoints), 2);
  EXPECT_EQ(Dropped(slam, DropReason::kScanTimeBackwards), 1);
  EXPECT_EQ(Dropped(slam, DropReason::kOdometryTimeBackwards), 1);
  EXPECT_GE(slam.counters().invalid_beams, static_cast<int64_t>(good.range_m.size()));
  EXPECT_EQ(h.poses.size(), poses_before);  // nothing published for them

  // The stream carries on as if nothing happened.
  h.RunFor(1.0);
  EXPECT_EQ(h.poses.size(), poses_before + 10);
  EXPECT_EQ(h.node().subscriptions().stats(channels::kLidarScan).rejected, 4);
  const std::string report = h.node().CountersReport();
  EXPECT_NE(report.find(DropReasonName(DropReason::kScanTooFewPoints)), std::string::npos);
}

}  // namespace
}  // namespace aslam
