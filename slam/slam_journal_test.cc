// The SLAM journal: what is written reads back into the same Slam; a Slam stopped mid-lap
// and resumed from its journal keeps its keyframe ids and "map" frame; damaged tails are cut.

#include "slam/slam_journal.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"
#include "common/world_file.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/simulator.h"

namespace aslam {
namespace {

const std::string kRoot = ASLAM_SOURCE_DIR;
using ::testing::HasSubstr;

// The lap of the test world (it closes a loop), fed scan by scan to whichever Slam
// `slam_for` returns for that scan; also returns the truth in "map" at each keyframe time.
class Lap {
 public:
  Lap()
      : world_(LoadWorld(kRoot + "/worlds/test")),
        drive_(LoadScriptedDrive(kRoot + "/config/drives/test_loop.yaml")) {}

  void Run(const std::function<Slam*(int scan_index)>& slam_for) {
    Simulator sim(world_.map.grid, world_.start, {});
    int scans = 0;
    while (const auto command = drive_.CommandAt(sim.utime())) {
      sim.SetCommand(*command);
      const SimStepOutput out = sim.Step();
      if (out.truth) truth_.emplace_back(out.truth->utime, world_.start.Between(out.truth->pose));
      Slam* slam = slam_for(scans);
      if (out.odometry) slam->AddOdometry(*out.odometry);
      if (out.scan) {
        slam->AddScan(*out.scan);
        ++scans;
      }
    }
  }

  double AteRmseM(const PoseGraph& graph) const {
    double sum_sq = 0.0;
    std::size_t t = 0;
    for (const PoseGraphNode& node : graph.nodes) {
      while (t + 1 < truth_.size() && truth_[t].first < node.utime) ++t;
      const double e =
          std::hypot(node.pose.x_m - truth_[t].second.x_m, node.pose.y_m - truth_[t].second.y_m);
      sum_sq += e * e;
    }
    return std::sqrt(sum_sq / graph.nodes.size());
  }

 private:
  WorldInfo world_;
  ScriptedDrive drive_;
  std::vector<std::pair<int64_t, Pose2d>> truth_;
};

void ExpectSameGraph(const PoseGraph& a, const PoseGraph& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].id, b.nodes[i].id);
    EXPECT_EQ(a.nodes[i].utime, b.nodes[i].utime);
    EXPECT_EQ(a.nodes[i].pose.x_m, b.nodes[i].pose.x_m) << "node " << i;
    EXPECT_EQ(a.nodes[i].pose.y_m, b.nodes[i].pose.y_m) << "node " << i;
    EXPECT_EQ(a.nodes[i].pose.yaw_rad, b.nodes[i].pose.yaw_rad) << "node " << i;
  }
  ASSERT_EQ(a.edges.size(), b.edges.size());
  for (std::size_t i = 0; i < a.edges.size(); ++i) {
    EXPECT_EQ(a.edges[i].from_id, b.edges[i].from_id);
    EXPECT_EQ(a.edges[i].to_id, b.edges[i].to_id);
    EXPECT_EQ(a.edges[i].kind, b.edges[i].kind);
    EXPECT_EQ(a.edges[i].measurement.x_m, b.edges[i].measurement.x_m);
    EXPECT_EQ(a.edges[i].information, b.edges[i].information);
  }
}

SlamOptions ExactMapOptions() {
  SlamOptions options;
  options.loop_closure.map_rerender_tolerance_m = 0.0;  // the map follows every move
  return options;
}

TEST(SlamJournal, ReadsBackIntoTheSameSlam) {
  Slam slam(ExactMapOptions());
  {
    SlamJournalWriter writer(TestTempPath("slam.journal"), 0);
    slam.set_journal(&writer);
    Lap().Run([&](int) { return &slam; });
    slam.set_journal(nullptr);
    ASSERT_FALSE(writer.error()) << *writer.error();
  }
  ASSERT_GE(slam.counters().loop_closures_accepted, 1);
  const SlamJournalRead read = ReadSlamJournal(TestTempPath("slam.journal"));
  EXPECT_FALSE(read.damage);
  EXPECT_EQ(read.valid_bytes,
            static_cast<int64_t>(std::filesystem::file_size(TestTempPath("slam.journal"))));

  Slam restored(ExactMapOptions());
  restored.Restore(read.snapshot);
  ExpectSameGraph(restored.graph(), slam.graph());
  EXPECT_EQ(restored.counters().loop_closures_accepted, slam.counters().loop_closures_accepted);
  EXPECT_EQ(restored.counters().keyframes_not_mapped, slam.counters().keyframes_not_mapped);
  // Counters are journaled with each keyframe: scans after the last one are not in it.
  EXPECT_LE(restored.counters().scans_processed, slam.counters().scans_processed);
  EXPECT_GT(restored.counters().scans_processed, slam.counters().scans_processed - 20);
  const OccupancyGrid original_map = slam.RenderMap();
  const OccupancyGrid restored_map = restored.RenderMap();
  // The grids grew differently (one keyframe at a time, or all at once): compare by place.
  int differing = 0, known = 0;
  for (int row = 0; row < restored_map.height_cells(); ++row) {
    for (int col = 0; col < restored_map.width_cells(); ++col) {
      const int8_t value = restored_map.at({col, row});
      const Point2d center = restored_map.CellCenter({col, row});
      const int8_t original = original_map.ValueOr(original_map.WorldToCell(center), -1);
      if (value != -1) ++known;
      if (value != original) ++differing;
    }
  }
  EXPECT_GT(known, 1000);
  EXPECT_EQ(differing, 0);
}

TEST(SlamJournal, AResumedSlamKeepsItsIdsAndFrame) {
  // The lap without interruption, for reference.
  Lap reference_lap;
  Slam reference(SlamOptions{});
  reference_lap.Run([&](int) { return &reference; });

  // The same lap, "killed" after a third of its scans and resumed from the journal.
  const std::string path = TestTempPath("slam.journal");
  Lap lap;
  auto first = std::make_unique<Slam>(SlamOptions{});
  auto writer = std::make_unique<SlamJournalWriter>(path, 0);
  first->set_journal(writer.get());
  std::unique_ptr<Slam> second;
  std::size_t keyframes_at_crash = 0;
  Pose2d last_pose_at_crash;
  constexpr int kCrashScan = 1000;  // after the lap's first loop closure
  lap.Run([&](int scan) -> Slam* {
    if (scan < kCrashScan) {
      if (first->latest_pose()) writer->Commit(first->latest_pose()->utime);
      return first.get();
    }
    if (!second) {
      EXPECT_GE(first->counters().loop_closures_accepted, 1);
      keyframes_at_crash = first->graph().nodes.size();
      last_pose_at_crash = first->graph().nodes.back().pose;
      first.reset();
      writer.reset();
      const SlamJournalRead read = ReadSlamJournal(path);
      EXPECT_FALSE(read.damage);
      second = std::make_unique<Slam>(SlamOptions{});
      second->Restore(read.snapshot);
      writer = std::make_unique<SlamJournalWriter>(path, read.valid_bytes);
      second->set_journal(writer.get());
    }
    return second.get();
  });
  ASSERT_TRUE(second);
  ASSERT_GT(keyframes_at_crash, 10u);
  const PoseGraph& graph = second->graph();
  ASSERT_GT(graph.nodes.size(), keyframes_at_crash + 5);
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) EXPECT_EQ(graph.nodes[i].id, (int)i);
  // The keyframe after the restart continues from the last one before it.
  const Pose2d step = last_pose_at_crash.Between(graph.nodes[keyframes_at_crash].pose);
  EXPECT_LT(std::hypot(step.x_m, step.y_m), 0.5);
  EXPECT_GE(second->counters().loop_closures_accepted, 1);
  const double resumed_rmse = lap.AteRmseM(graph);
  const double reference_rmse = reference_lap.AteRmseM(reference.graph());
  std::printf(
      "lap: reference %zu keyframes, ATE %.3f m; resumed at keyframe %zu: %zu, ATE %.3f m\n",
      reference.graph().nodes.size(), reference_rmse, keyframes_at_crash, graph.nodes.size(),
      resumed_rmse);
  EXPECT_LT(resumed_rmse, 0.10);

  // The journal now holds both lives: read back, it is the resumed Slam.
  writer->Sync();
  const SlamJournalRead all = ReadSlamJournal(path);
  EXPECT_FALSE(all.damage);
  ExpectSameGraph(all.snapshot.graph, graph);
}

// Rewritten from the Slam's snapshot after the loop closures, the journal reads back into the
// same Slam, is smaller than the one that kept every optimization's poses, and what the
// rest of the lap appends to it reads back too.
TEST(SlamJournal, ARewriteHoldsTheSameSlamInLessSpaceAndAppendingGoesOn) {
  int64_t appended_only_bytes = 0;
  int scans = 0;
  {
    Slam reference(ExactMapOptions());
    SlamJournalWriter writer(TestTempPath("appended.journal"), 0);
    reference.set_journal(&writer);
    Lap().Run([&](int scan) {
      scans = scan + 1;
      return &reference;
    });
    reference.set_journal(nullptr);
    writer.Sync();
    appended_only_bytes = writer.bytes_written();
  }
  const std::string path = TestTempPath("slam.journal");
  Slam slam(ExactMapOptions());
  SlamJournalWriter writer(path, 0);
  slam.set_journal(&writer);
  const int rewrite_scan = scans - 30;  // after the lap's closures, before its last keyframes
  std::size_t keyframes_at_rewrite = 0;
  Lap().Run([&](int scan) {
    if (scan == rewrite_scan && writer.rewrites() == 0) {  // called every tick, not every scan
      std::string why_not;
      EXPECT_TRUE(writer.Rewrite(slam.Snapshot(), &why_not)) << why_not;
      keyframes_at_rewrite = slam.graph().nodes.size();
    }
    return &slam;
  });
  slam.set_journal(nullptr);
  writer.Sync();
  ASSERT_FALSE(writer.error());
  EXPECT_EQ(writer.rewrites(), 1);
  ASSERT_GE(slam.counters().optimizations, 1);
  EXPECT_GT(slam.graph().nodes.size(), keyframes_at_rewrite) << "keyframes appended after it";
  EXPECT_FALSE(std::filesystem::exists(path + ".rewrite"));

  const SlamJournalRead read = ReadSlamJournal(path);
  EXPECT_FALSE(read.damage);
  EXPECT_EQ(read.valid_bytes, static_cast<int64_t>(std::filesystem::file_size(path)));
  EXPECT_LT(read.valid_bytes, appended_only_bytes);
  ExpectSameGraph(read.snapshot.graph, slam.graph());
  ASSERT_EQ(read.snapshot.keyframes.size(), slam.graph().nodes.size());
  const SlamSnapshot live = slam.Snapshot();
  for (std::size_t i = 0; i < live.keyframes.size(); ++i) {
    EXPECT_EQ(read.snapshot.keyframes[i].utime, live.keyframes[i].utime);
    EXPECT_EQ(read.snapshot.keyframes[i].in_map, live.keyframes[i].in_map);
    EXPECT_EQ(read.snapshot.keyframes[i].scan.range_m, live.keyframes[i].scan.range_m);
  }
  EXPECT_EQ(read.snapshot.state.counters.loop_closures_accepted,
            slam.counters().loop_closures_accepted);
  Slam restored(ExactMapOptions());
  restored.Restore(read.snapshot);
  ExpectSameGraph(restored.graph(), slam.graph());
}

// Optimization records past half of a journal over 1 MiB ask for a rewrite.
TEST(SlamJournal, WantsARewriteOncePosesAreMostOfIt) {
  SlamJournalWriter writer(TestTempPath("slam.journal"), 0);
  EXPECT_FALSE(writer.WantsRewrite());
  const std::vector<PoseGraphNode> nodes(1000, PoseGraphNode{0, 0, {1.0, 2.0, 0.5}});
  int64_t utime = 0;
  while (!writer.WantsRewrite() && utime < 1000) {
    writer.OnOptimized(nodes);
    writer.Commit(++utime);
  }
  EXPECT_TRUE(writer.WantsRewrite());
  EXPECT_GT(writer.bytes_written(), int64_t{1} << 20);
  std::string why_not;
  ASSERT_TRUE(writer.Rewrite(SlamSnapshot{}, &why_not)) << why_not;
  EXPECT_FALSE(writer.WantsRewrite());
  EXPECT_EQ(ReadSlamJournal(TestTempPath("slam.journal")).records, 1);  // the state
}

TEST(SlamJournal, ADamagedTailIsCutAndWritingGoesOnAfterTheLastWholeRecord) {
  const std::string path = TestTempPath("slam.journal");
  Slam slam(SlamOptions{});
  {
    SlamJournalWriter writer(path, 0);
    slam.set_journal(&writer);
    Lap().Run([&](int) { return &slam; });
    slam.set_journal(nullptr);
  }
  const SlamJournalRead whole = ReadSlamJournal(path);
  ASSERT_FALSE(whole.damage);
  const auto size = std::filesystem::file_size(path);

  // A crash mid-write: the last record loses its end.
  std::filesystem::resize_file(path, size - 7);
  const SlamJournalRead cut = ReadSlamJournal(path);
  ASSERT_TRUE(cut.damage);
  EXPECT_THAT(*cut.damage, HasSubstr("cut short"));
  EXPECT_EQ(cut.records, whole.records - 1);
  EXPECT_LT(cut.valid_bytes, static_cast<int64_t>(size - 7));

  // A flipped byte inside an earlier record: everything from that record on is left out.
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(size / 2));
    char byte = 0;
    file.read(&byte, 1);
    file.seekp(static_cast<std::streamoff>(size / 2));
    byte = static_cast<char>(byte ^ 0x5a);
    file.write(&byte, 1);
  }
  const SlamJournalRead flipped = ReadSlamJournal(path);
  ASSERT_TRUE(flipped.damage);
  EXPECT_THAT(*flipped.damage, HasSubstr("CRC"));
  EXPECT_LT(flipped.records, cut.records);
  EXPECT_GT(flipped.records, 0);

  // Reopened for writing, the file is cut after the last whole record and new records follow.
  Slam resumed(SlamOptions{});
  resumed.Restore(flipped.snapshot);
  {
    SlamJournalWriter writer(path, flipped.valid_bytes);
    writer.OnState(SlamState{});
  }
  const SlamJournalRead again = ReadSlamJournal(path);
  EXPECT_FALSE(again.damage);
  EXPECT_EQ(again.records, flipped.records + 1);
}

TEST(SlamJournal, NotAJournalIsAnErrorNamingThePath) {
  const std::string path = TestTempPath("map.yaml");
  std::ofstream(path) << "image: map.pgm\n";
  try {
    ReadSlamJournal(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr(path));
    EXPECT_THAT(e.what(), HasSubstr("not an aslam SLAM journal"));
  }
  EXPECT_THROW(ReadSlamJournal(TestTempPath("missing")), std::runtime_error);
  EXPECT_THROW(SlamJournalWriter(TestTempPath("no/such/dir/slam.journal"), 0), std::runtime_error);
}

}  // namespace
}  // namespace aslam
