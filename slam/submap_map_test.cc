#include "slam/submap_map.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

// A 360° scan of `beams` beams with ranges from `rng` in [0.5, 3.5] m; every 23rd has no return.
LidarScan RandomScan(std::mt19937& rng, int beams) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  LidarScan scan;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2.0 * M_PI / beams;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  for (int i = 0; i < beams; ++i) {
    scan.range_m.push_back(i % 23 == 0 ? 0.0f : static_cast<float>(0.5 + 3.0 * unit(rng)));
  }
  return scan;
}

// `count` random scans at random poses in [0, 3] x [0, 2] m, any heading.
struct PosedScans {
  std::vector<LidarScan> scans;
  std::vector<Pose2d> poses;
};
PosedScans RandomPosedScans(unsigned seed, int count, int beams) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PosedScans out;
  for (int s = 0; s < count; ++s) {
    out.scans.push_back(RandomScan(rng, beams));
    out.poses.push_back({3.0 * unit(rng), 2.0 * unit(rng), 6.0 * unit(rng)});
  }
  return out;
}

// Thresholds that render every log-odds value apart, so any difference in a sum shows.
OccupancyMapperOptions FineOptions(int submap_keyframes) {
  OccupancyMapperOptions options;
  options.free_threshold = 0.01;
  options.occupied_threshold = 0.99;
  options.no_return_clear_m = 1.5;  // no-return beams end in a miss
  options.submap_keyframes = submap_keyframes;
  return options;
}

// Every cell of `expected` read at its centre in `actual`, and the same number of known cells.
void ExpectSameMap(const OccupancyGrid& actual, const OccupancyGrid& expected) {
  int known = 0;
  for (int row = 0; row < expected.height_cells(); ++row) {
    for (int col = 0; col < expected.width_cells(); ++col) {
      const Point2d centre = expected.CellCenter({col, row});
      // Off the grid reads unknown: how far the grid's unknown border reaches does not matter.
      ASSERT_EQ(actual.ValueOr(actual.WorldToCell(centre), OccupancyGrid::kUnknown),
                expected.at({col, row}))
          << "at (" << centre.x_m << ", " << centre.y_m << ")";
      known += expected.at({col, row}) != OccupancyGrid::kUnknown;
    }
  }
  int actual_known = 0;
  for (const int8_t value : actual.cells()) actual_known += value != OccupancyGrid::kUnknown;
  EXPECT_EQ(actual_known, known);
  EXPECT_GT(known, 1000);
}

// Scans 3 at a time per submap: the submaps are clamped grids of their own scans, and the map
// is their sum. Six identical scans: a cell each beam passes is missed 3 times per submap
// (3 x -0.4 = -1.2, inside the clamp) and the map sums two submaps to -2.4, where one grid
// would have clamped at log_odds_min = -2.
TEST(SubmapMapTest, SubmapsAreClampedGridsAndTheMapIsTheirSum) {
  OccupancyMapperOptions options = FineOptions(3);
  options.no_return_clear_m = 0.0;
  SubmapMap map(options);
  LidarScan scan;
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = 0.0;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.range_m = {2.0f};  // one beam along +x, a hit 2 m ahead
  std::vector<int> submaps;
  for (int i = 0; i < 6; ++i) submaps.push_back(map.InsertScan({0.01, 0.01, 0.0}, scan));
  EXPECT_EQ(submaps, (std::vector<int>{0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(map.num_submaps(), 2);
  const OccupancyGrid grid = map.Render();
  auto percent = [](double log_odds) {
    return static_cast<int>(std::lround(100.0 / (1.0 + std::exp(-log_odds))));
  };
  const int8_t missed = grid.ValueOr(grid.WorldToCell({1.0, 0.01}), -2);
  EXPECT_EQ(missed, percent(2 * 3 * options.log_odds_miss));
  const int8_t hit = grid.ValueOr(grid.WorldToCell({2.02, 0.01}), -2);
  EXPECT_EQ(hit, OccupancyGrid::kOccupied);  // 2 x min(3 x 0.85, 3.5) = 5.1: p > 0.99
  EXPECT_EQ(grid.ValueOr(grid.WorldToCell({1.0, 1.0}), -2), OccupancyGrid::kUnknown);
}

// Moving the scans of a closed submap and of the open one, then re-rendering those two
// submaps, leaves the map a fresh insertion at the new poses would give, cell for cell.
TEST(SubmapMapTest, RerenderedSubmapsEqualAFreshMapWithTheScansMoved) {
  PosedScans posed = RandomPosedScans(11, 8, 361);
  const std::vector<LidarScan>& scans = posed.scans;
  std::vector<Pose2d>& poses = posed.poses;
  SubmapMap map(FineOptions(3));  // submaps {0, 1, 2}, {3, 4, 5}, {6, 7} (open)
  for (std::size_t s = 0; s < scans.size(); ++s) map.InsertScan(poses[s], scans[s]);
  ASSERT_EQ(map.num_submaps(), 3);
  for (const int s : {3, 4, 7}) poses[s] = poses[s].Compose({0.11, -0.07, 0.05});
  poses[6] = {9.0, 0.0, 0.0};  // far away: the map must grow for it
  map.RerenderSubmap(1, {{poses[3], &scans[3]}, {poses[4], &scans[4]}, {poses[5], &scans[5]}});
  map.RerenderSubmap(2, {{poses[6], &scans[6]}, {poses[7], &scans[7]}});

  SubmapMap fresh(FineOptions(3));
  for (std::size_t s = 0; s < scans.size(); ++s) fresh.InsertScan(poses[s], scans[s]);
  ExpectSameMap(map.Render(), fresh.Render());
}

// Render() redraws only the cells changed since its last call. Rendered after every step of
// inserts (some far off, so the map grows) and re-renders of moved submaps, it matches a map
// built from scratch at the same poses and rendered once.
TEST(SubmapMapTest, RenderingOnlyChangedCellsMatchesAWholeRender) {
  PosedScans posed = RandomPosedScans(23, 10, 181);
  const std::vector<LidarScan>& scans = posed.scans;
  std::vector<Pose2d>& poses = posed.poses;
  poses[6].x_m += 12.0;  // far off: the map grows
  SubmapMap map(FineOptions(3));
  std::vector<std::vector<int>> members;
  auto from_scratch = [&](int num_scans) {
    SubmapMap fresh(FineOptions(3));
    for (int s = 0; s < num_scans; ++s) fresh.InsertScan(poses[s], scans[s]);
    return fresh.Render();
  };
  for (int s = 0; s < 10; ++s) {
    const int submap = map.InsertScan(poses[s], scans[s]);
    if (submap >= static_cast<int>(members.size())) members.resize(submap + 1);
    members[submap].push_back(s);
    ExpectSameMap(map.Render(), from_scratch(s + 1));
    if (s == 4 || s == 8) {
      const int moved = s == 4 ? 0 : 2;  // a closed submap, then the open one
      std::vector<SubmapMap::PosedScan> rerender;
      for (const int m : members[moved]) {
        poses[m] = poses[m].Compose({0.13, 0.05, -0.04});
        rerender.push_back({poses[m], &scans[m]});
      }
      map.RerenderSubmap(moved, rerender);
      ExpectSameMap(map.Render(), from_scratch(s + 1));
    }
  }
  ASSERT_EQ(map.num_submaps(), 4);
}

// Taking a submap out of the sum and putting it back is exact: re-rendering unmoved
// submaps any number of times changes no cell.
TEST(SubmapMapTest, RerenderingUnmovedSubmapsKeepsTheMap) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<LidarScan> scans;
  std::vector<Pose2d> poses;
  SubmapMap map(FineOptions(2));
  std::vector<std::vector<SubmapMap::PosedScan>> members(4);
  for (int s = 0; s < 7; ++s) {
    scans.push_back(RandomScan(rng, 181));
    poses.push_back({2.0 * unit(rng), 2.0 * unit(rng), 6.0 * unit(rng)});
  }
  for (int s = 0; s < 7; ++s)
    members[map.InsertScan(poses[s], scans[s])].push_back({poses[s], &scans[s]});
  const OccupancyGrid before = map.Render();
  for (int trial = 0; trial < 12; ++trial) {
    const int submap = trial % map.num_submaps();
    map.RerenderSubmap(submap, members[submap]);
    const OccupancyGrid after = map.Render();
    ASSERT_EQ(after.width_cells(), before.width_cells());
    ASSERT_EQ(after.cells(), before.cells()) << "trial " << trial;
  }
}

// Revealed cells are those no submap has observed, closed or open: the same cells one grid
// of every scan has never observed, whatever the clamps did to their values.
TEST(SubmapMapTest, CountRevealedCellsLooksAtEverySubmap) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SubmapMap map(FineOptions(2));
  OccupancyMapper single(FineOptions(2));
  const LidarScan probe = RandomScan(rng, 181);
  const Pose2d probe_pose{2.0, 1.0, 0.3};
  const int before = map.CountRevealedCells(probe_pose, probe);
  EXPECT_GT(before, 1000);
  for (int s = 0; s < 5; ++s) {
    const LidarScan scan = RandomScan(rng, 181);
    const Pose2d pose{4.0 * unit(rng), 2.0 * unit(rng), 6.0 * unit(rng)};
    map.InsertScan(pose, scan);
    single.InsertScan(pose, scan);
    for (const Pose2d& at : {probe_pose, pose, Pose2d{-1.0, 3.0, 2.0}}) {
      EXPECT_EQ(map.CountRevealedCells(at, probe), single.CountRevealedCells(at, probe))
          << "after " << s + 1 << " scans";
    }
  }
  EXPECT_EQ(map.num_submaps(), 3);
  EXPECT_LT(map.CountRevealedCells(probe_pose, probe), before / 2);
}

TEST(SubmapMapTest, BadOptionsAndUnknownSubmapsThrow) {
  OccupancyMapperOptions options;
  options.submap_keyframes = 0;
  try {
    SubmapMap bad(options);
    FAIL() << "submap_keyframes = 0 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("submap_keyframes"), std::string::npos) << e.what();
  }
  SubmapMap map({});
  EXPECT_TRUE(map.empty());
  EXPECT_TRUE(map.Render().empty());
  EXPECT_THROW(map.RerenderSubmap(0, {}), std::out_of_range);
}

}  // namespace
}  // namespace aslam
