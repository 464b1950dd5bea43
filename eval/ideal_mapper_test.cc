#include "eval/ideal_mapper.h"

#include <cmath>

#include <gtest/gtest.h>

namespace aslam {
namespace {

constexpr double kWallX_m = 3.0;    // a wall along x = 3 m in the world
constexpr double kTurnRadps = 2.0;  // the robot turns in place at the world's origin
constexpr double kSweepS = 0.2;

// A swept scan starting at `utime` while the robot turns: each beam's range is what it measures
// from the true heading at its own time.
LidarScan SweptScanOfTheWall(int64_t utime, double yaw_at_utime_rad) {
  LidarScan scan;
  scan.utime = utime;
  scan.angle_min_rad = -0.6;
  scan.angle_increment_rad = 0.01;
  scan.range_min_m = 0.1;
  scan.range_max_m = 12.0;
  for (int i = 0; i <= 120; ++i) {
    const double t_s = kSweepS * i / 120.0;
    const double world_angle = yaw_at_utime_rad + kTurnRadps * t_s + scan.BeamAngle(i);
    scan.range_m.push_back(static_cast<float>(kWallX_m / std::cos(world_angle)));
    scan.beam_time_s.push_back(static_cast<float>(t_s));
  }
  return scan;
}

void AddTurningTruth(IdealMapper* mapper, int64_t from_utime, int64_t to_utime) {
  for (int64_t t = from_utime; t <= to_utime; t += 20'000) {
    mapper->AddTruth({t, Pose2d{0.0, 0.0, kTurnRadps * t * 1e-6}});
  }
}

TEST(IdealMapper, EveryBeamIsPlacedByTheTrueMotionAtItsTime) {
  IdealMapper mapper({}, {});
  AddTurningTruth(&mapper, 0, 300'000);
  const auto pose = mapper.AddScan(SweptScanOfTheWall(0, 0.0));
  ASSERT_TRUE(pose.has_value());
  EXPECT_NEAR(pose->yaw_rad, 0.0, 1e-12);  // the first scan's pose is the map's origin

  // Every occupied cell lies on the wall; taking the beams as one instant would bend it
  // (0.4 rad of turn over the sweep).
  const OccupancyGrid map = mapper.RenderMap();
  int occupied = 0;
  for (int row = 0; row < map.height_cells(); ++row) {
    for (int col = 0; col < map.width_cells(); ++col) {
      if (map.at({col, row}) < 65) continue;
      ++occupied;
      const Point2d p = map.CellCenter({col, row});
      EXPECT_NEAR(p.x_m, kWallX_m, 0.08) << "cell at (" << p.x_m << ", " << p.y_m << ")";
    }
  }
  EXPECT_GT(occupied, 60);
}

TEST(IdealMapper, TheMapFrameIsTheFirstScansTruePose) {
  IdealMapper mapper({}, {});
  AddTurningTruth(&mapper, 0, 1'000'000);
  ASSERT_TRUE(mapper.AddScan(SweptScanOfTheWall(250'000, 0.5)).has_value());
  const auto later = mapper.AddScan(SweptScanOfTheWall(750'000, 1.5));
  ASSERT_TRUE(later.has_value());
  EXPECT_NEAR(later->yaw_rad, 1.0, 1e-9);  // 0.5 s later at 2 rad/s, relative to the first
  // Keyframes: the first, and the second after 1 rad of rotation.
  ASSERT_EQ(mapper.graph().nodes.size(), 2u);
  EXPECT_EQ(mapper.graph().nodes[1].utime, 750'000);
  EXPECT_TRUE(mapper.graph().edges.empty());
}

TEST(IdealMapper, NoTruthNearTheScanMapsNothing) {
  IdealMapper mapper({}, {});
  EXPECT_FALSE(mapper.AddScan(SweptScanOfTheWall(0, 0.0)).has_value());
  AddTurningTruth(&mapper, 0, 100'000);
  EXPECT_FALSE(mapper.AddScan(SweptScanOfTheWall(5'000'000, 0.0)).has_value());
  EXPECT_TRUE(mapper.RenderMap().empty());
  EXPECT_EQ(mapper.newest_truth_utime(), 100'000);
}

}  // namespace
}  // namespace aslam
