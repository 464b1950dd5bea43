#include "slam/occupancy_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace aslam {
namespace {

// The cell value Render() should give for a log-odds value under the default thresholds.
int8_t Percent(double log_odds) {
  const double p = 1.0 / (1.0 + std::exp(-log_odds));
  const OccupancyMapperOptions defaults;
  if (p <= defaults.free_threshold) return OccupancyGrid::kFree;
  if (p >= defaults.occupied_threshold) return OccupancyGrid::kOccupied;
  return static_cast<int8_t>(std::lround(100.0 * p));
}

// A scan whose beams all point along the sensor's x axis.
LidarScan ForwardScan(std::vector<float> ranges_m) {
  LidarScan scan;
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = 0.0;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.range_m = std::move(ranges_m);
  return scan;
}

LidarScan OneBeam(double angle_rad, float range_m) {
  LidarScan scan = ForwardScan({range_m});
  scan.angle_min_rad = angle_rad;
  return scan;
}

int8_t At(const OccupancyGrid& grid, double x_m, double y_m) {
  return grid.ValueOr(grid.WorldToCell({x_m, y_m}), -2);  // -2: off the grid
}

// Base inside cell (0, 0) of the world cell lattice, at 5 cm resolution.
constexpr double kX = 0.01, kY = 0.01, kRes = 0.05;
double CellCenterM(int index) { return (index + 0.5) * kRes; }

TEST(OccupancyMapperTest, BeamAlongARowMarksFreeCellsThenAnOccupiedEndCell) {
  const OccupancyMapperOptions options;
  OccupancyMapper mapper(options);
  EXPECT_TRUE(mapper.empty());
  mapper.InsertScan({kX, kY, 0.0}, OneBeam(0.0, 1.0f));  // ends at x = 1.01 m: cell 20
  EXPECT_FALSE(mapper.empty());
  const OccupancyGrid grid = mapper.Render();
  EXPECT_DOUBLE_EQ(grid.resolution_m(), kRes);
  for (int col = 0; col < 20; ++col) {
    EXPECT_EQ(At(grid, CellCenterM(col), CellCenterM(0)), Percent(options.log_odds_miss))
        << "col " << col;
  }
  EXPECT_EQ(At(grid, CellCenterM(20), CellCenterM(0)), Percent(options.log_odds_hit));
  // Beyond the end, behind the sensor and beside the beam: never observed.
  EXPECT_EQ(At(grid, CellCenterM(21), CellCenterM(0)), OccupancyGrid::kUnknown);
  EXPECT_EQ(At(grid, CellCenterM(-1), CellCenterM(0)), OccupancyGrid::kUnknown);
  EXPECT_EQ(At(grid, CellCenterM(10), CellCenterM(1)), OccupancyGrid::kUnknown);
  EXPECT_EQ(At(grid, CellCenterM(10), CellCenterM(-1)), OccupancyGrid::kUnknown);
  const OccupancyGrid::CellCounts counts = grid.CountCells();
  EXPECT_EQ(counts.free + counts.occupied, 21u);  // nothing else was touched
}

TEST(OccupancyMapperTest, DiagonalBeamAndSensorOffsetFollowTheSensorFrame) {
  OccupancyMapper mapper({});
  LidarScan scan = OneBeam(M_PI / 4, static_cast<float>(10 * kRes * std::sqrt(2.0)));
  scan.sensor_pose = {0.0, 0.1, 0.0};  // sensor 2 cells left of the base (base faces +y)
  mapper.InsertScan({kX + 0.1, kY, M_PI / 2}, scan);  // sensor at cell (0, 0), beam to (-10, 10)
  const OccupancyGrid grid = mapper.Render();
  for (int k = 0; k < 10; ++k) {
    EXPECT_LT(At(grid, CellCenterM(-k), CellCenterM(k)), 50) << "k " << k;
    EXPECT_GE(At(grid, CellCenterM(-k), CellCenterM(k)), 0) << "k " << k;
  }
  EXPECT_GT(At(grid, CellCenterM(-10), CellCenterM(10)), 50);
}

TEST(OccupancyMapperTest, RepeatedScansSaturateAtTheClamps) {
  const OccupancyMapperOptions options;
  OccupancyMapper mapper(options);
  for (int i = 0; i < 30; ++i) mapper.InsertScan({kX, kY, 0.0}, OneBeam(0.0, 1.0f));
  const OccupancyGrid grid = mapper.Render();
  EXPECT_EQ(At(grid, CellCenterM(20), CellCenterM(0)), Percent(options.log_odds_max));
  EXPECT_EQ(At(grid, CellCenterM(5), CellCenterM(0)), Percent(options.log_odds_min));
  // The clamp lets the map change again: a few misses bring the wall down.
  for (int i = 0; i < 10; ++i) mapper.InsertScan({kX, kY, 0.0}, OneBeam(0.0, 2.0f));
  EXPECT_LT(At(mapper.Render(), CellCenterM(20), CellCenterM(0)), 50);
}

TEST(OccupancyMapperTest, AHitBeatsAMissOfAnotherBeamInTheSameScan) {
  const OccupancyMapperOptions options;
  OccupancyMapper mapper(options);
  mapper.InsertScan({kX, kY, 0.0}, ForwardScan({0.5f, 1.0f}));  // ends at cells 10 and 20
  const OccupancyGrid grid = mapper.Render();
  EXPECT_EQ(At(grid, CellCenterM(10), CellCenterM(0)), Percent(options.log_odds_hit));
  EXPECT_EQ(At(grid, CellCenterM(20), CellCenterM(0)), Percent(options.log_odds_hit));
  // Two beams through cell 5, but one update per scan.
  EXPECT_EQ(At(grid, CellCenterM(5), CellCenterM(0)), Percent(options.log_odds_miss));
}

TEST(OccupancyMapperTest, GrowingKeepsCellsAtTheirWorldPositions) {
  OccupancyMapperOptions options;
  options.growth_margin_m = 0.3;
  OccupancyMapper mapper(options);
  mapper.InsertScan({kX, kY, 0.0}, OneBeam(0.0, 1.0f));
  const OccupancyGrid before = mapper.Render();
  // Far to the south-west, and then north-east: the grid must grow both ways.
  mapper.InsertScan({-7.33, -4.71, 0.3}, OneBeam(0.0, 3.0f));
  mapper.InsertScan({6.2, 5.9, -2.0}, OneBeam(0.0, 3.0f));
  const OccupancyGrid after = mapper.Render();
  EXPECT_GT(after.width_cells(), before.width_cells());
  EXPECT_GT(after.height_cells(), before.height_cells());
  EXPECT_LT(after.origin_m().x_m, before.origin_m().x_m - 7.0);
  EXPECT_LT(after.origin_m().y_m, before.origin_m().y_m - 4.0);
  // The origin stays on the resolution lattice, so old cells map onto new ones.
  const double cols = after.origin_m().x_m / kRes, rows = after.origin_m().y_m / kRes;
  EXPECT_NEAR(cols, std::round(cols), 1e-9);
  EXPECT_NEAR(rows, std::round(rows), 1e-9);
  for (int col = -2; col <= 22; ++col) {
    for (int row = -1; row <= 1; ++row) {
      EXPECT_EQ(At(after, CellCenterM(col), CellCenterM(row)),
                before.ValueOr(before.WorldToCell({CellCenterM(col), CellCenterM(row)}), -1))
          << "col " << col << " row " << row;
    }
  }
}

TEST(OccupancyMapperTest, NoReturnBeamsAreIgnoredOrClearPerOption) {
  const LidarScan no_return = OneBeam(0.0, 0.0f);
  OccupancyMapper ignore({});  // no_return_clear_m = 0
  ignore.InsertScan({kX, kY, 0.0}, no_return);
  EXPECT_TRUE(ignore.empty());
  EXPECT_TRUE(ignore.Render().empty());

  OccupancyMapperOptions options;
  options.no_return_clear_m = 0.5;
  OccupancyMapper clear(options);
  clear.InsertScan({kX, kY, 0.0}, no_return);  // clears to x = 0.51 m: cells 0..10
  const OccupancyGrid grid = clear.Render();
  for (int col = 0; col <= 10; ++col) {
    EXPECT_EQ(At(grid, CellCenterM(col), CellCenterM(0)), Percent(options.log_odds_miss))
        << "col " << col;
  }
  EXPECT_EQ(At(grid, CellCenterM(11), CellCenterM(0)), OccupancyGrid::kUnknown);
  for (int8_t value : grid.cells()) EXPECT_LT(value, 50);  // no hit anywhere
}

TEST(OccupancyMapperTest, InvalidBeamsAreSkipped) {
  OccupancyMapperOptions options;
  options.no_return_clear_m = 0.5;  // and they are not mistaken for no-return beams
  OccupancyMapper mapper(options);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  mapper.InsertScan({kX, kY, 0.0}, ForwardScan({nan, inf, -1.0f, 0.05f, 11.0f}));
  EXPECT_TRUE(mapper.empty());
}

TEST(OccupancyMapperTest, ClearForgetsAndReinsertingReproducesTheMap) {
  OccupancyMapper mapper({});
  LidarScan scan = ForwardScan({});
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2.0 * M_PI / 90;
  for (int i = 0; i < 90; ++i) scan.range_m.push_back(1.0f + 0.02f * (i % 7));
  mapper.InsertScan({0.3, -0.2, 0.1}, scan);
  mapper.InsertScan({0.8, 0.1, 0.5}, scan);
  const OccupancyGrid first = mapper.Render();
  mapper.Clear();
  EXPECT_TRUE(mapper.empty());
  EXPECT_TRUE(mapper.Render().empty());
  mapper.InsertScan({0.3, -0.2, 0.1}, scan);
  mapper.InsertScan({0.8, 0.1, 0.5}, scan);
  const OccupancyGrid second = mapper.Render();
  ASSERT_EQ(second.width_cells(), first.width_cells());
  ASSERT_EQ(second.height_cells(), first.height_cells());
  EXPECT_EQ(second.cells(), first.cells());
}

// A fan of beams ending on a wall 2 m ahead: into an empty map it reveals every cell it
// crosses; inserted, it reveals nothing more from where it was taken, and from 1 m farther
// back only the cells of that first metre (and the fan's wider sweep of them).
TEST(OccupancyMapperTest, CountRevealedCellsCountsNeverObservedCellsTheBeamsCross) {
  OccupancyMapper mapper(OccupancyMapperOptions{});
  LidarScan fan = ForwardScan({});
  fan.angle_min_rad = -0.4;
  fan.angle_increment_rad = 0.01;
  for (int i = 0; i <= 80; ++i) {
    fan.range_m.push_back(static_cast<float>(2.0 / std::cos(fan.BeamAngle(i))));
  }
  const Pose2d base{kX, kY, 0.0};
  const int into_empty = mapper.CountRevealedCells(base, fan);
  EXPECT_GE(into_empty, 81 * 40);  // each beam crosses at least 2 m / 5 cm cells
  EXPECT_LE(into_empty, 81 * 60);
  EXPECT_TRUE(mapper.empty());  // counting changed nothing
  mapper.InsertScan(base, fan);
  EXPECT_EQ(mapper.CountRevealedCells(base, fan), 0);
  const Pose2d back{kX - 1.0, kY, 0.0};
  const int from_back = mapper.CountRevealedCells(back, fan);
  EXPECT_GE(from_back, 81 * 20);  // the metre behind the first pose, at least
  EXPECT_LT(from_back, into_empty);
  // Off the grid counts as never observed.
  EXPECT_NEAR(mapper.CountRevealedCells({kX + 50.0, kY, 0.0}, fan), into_empty, 0.05 * into_empty);
}

TEST(OccupancyMapperTest, BadOptionsThrowNamingTheOption) {
  OccupancyMapperOptions options;
  options.resolution_m = 0.0;
  try {
    OccupancyMapper mapper(options);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("resolution_m"), std::string::npos);
  }
  options = {};
  options.log_odds_miss = 0.4;
  EXPECT_THROW(OccupancyMapper{options}, std::invalid_argument);
}

}  // namespace
}  // namespace aslam
