#include "navigation/costmap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace aslam {
namespace {

constexpr double kRes = 0.05;

// A random map: obstacles (values at or above the threshold), unknown cells
// and free cells of assorted occupancy values below the threshold.
OccupancyGrid RandomGrid(std::mt19937& rng, int width, int height, double obstacle_p,
                         double unknown_p) {
  OccupancyGrid grid(width, height, kRes, {-0.3, 0.7});
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::uniform_int_distribution<int> free_value(0, 64);
  std::uniform_int_distribution<int> occupied_value(65, 100);
  for (int8_t& value : grid.mutable_cells()) {
    const double draw = u01(rng);
    if (draw < obstacle_p) {
      value = static_cast<int8_t>(occupied_value(rng));
    } else if (draw < obstacle_p + unknown_p) {
      value = OccupancyGrid::kUnknown;
    } else {
      value = static_cast<int8_t>(u01(rng) < 0.5 ? 0 : free_value(rng));
    }
  }
  return grid;
}

// Nearest obstacle cell centre by looping over every obstacle cell, metres.
double BruteForceDistanceM(const OccupancyGrid& grid, CellIndex cell, int threshold) {
  double best = std::numeric_limits<double>::infinity();
  for (int row = 0; row < grid.height_cells(); ++row) {
    for (int col = 0; col < grid.width_cells(); ++col) {
      if (grid.at({col, row}) >= threshold) {
        best = std::min(best, std::hypot(col - cell.col, row - cell.row) * grid.resolution_m());
      }
    }
  }
  return best;
}

TEST(CostmapTest, DistanceMatchesBruteForceNearestObstacle) {
  for (int seed = 0; seed < 60; ++seed) {
    std::mt19937 rng(seed);
    const int width = 5 + seed % 23;
    const int height = 4 + (seed * 7) % 19;
    const OccupancyGrid grid = RandomGrid(rng, width, height, 0.02 + 0.01 * (seed % 10), 0.2);
    CostmapOptions options;
    options.occupied_threshold = 65;
    const Costmap costmap(grid, options);
    for (int row = 0; row < height; ++row) {
      for (int col = 0; col < width; ++col) {
        const double expected = BruteForceDistanceM(grid, {col, row}, 65);
        const double actual = costmap.ObstacleDistanceM({col, row});
        if (std::isinf(expected)) {
          EXPECT_TRUE(std::isinf(actual)) << "seed " << seed;
        } else {
          ASSERT_NEAR(actual, expected, 1e-5) << "seed " << seed << " cell " << col << "," << row;
        }
      }
    }
  }
}

// The documented cost of a cell at obstacle distance d, or -1 when d is too
// close to a band edge or a rounding tie for float rounding to be decisive.
int ExpectedCost(double d, const CostmapOptions& o) {
  const double radius = o.robot_radius_m + o.clearance_margin_m;
  const double outer = radius + o.inflation_margin_m;
  if (d == 0.0) return Costmap::kLethal;
  if (std::abs(d - radius) < 1e-6 || std::abs(d - outer) < 1e-6) return -1;
  if (d < radius) return Costmap::kInscribed;
  if (d > outer) return Costmap::kFree;
  const double value = 252.0 * std::exp(-o.cost_scaling_per_m * (d - radius));
  if (std::abs(value - std::floor(value) - 0.5) < 1e-3) return -1;
  return static_cast<int>(std::lround(value));
}

TEST(CostmapTest, CostsFollowBruteForceDistance) {
  int checked = 0;
  for (int seed = 0; seed < 40; ++seed) {
    std::mt19937 rng(1000 + seed);
    const OccupancyGrid grid = RandomGrid(rng, 30, 25, 0.01 + 0.005 * (seed % 5), 0.2);
    CostmapOptions options;
    options.robot_radius_m = 0.05 + 0.02 * (seed % 6);
    options.clearance_margin_m = 0.01 * (seed % 3);
    options.inflation_margin_m = 0.1 + 0.1 * (seed % 4);
    options.cost_scaling_per_m = 2.0 + seed % 7;
    options.unknown_passable = seed % 2 == 0;
    const Costmap costmap(grid, options);
    for (int row = 0; row < grid.height_cells(); ++row) {
      for (int col = 0; col < grid.width_cells(); ++col) {
        const CellIndex cell{col, row};
        const bool unknown = grid.at(cell) < 0;
        EXPECT_EQ(costmap.IsUnknown(cell), unknown);
        if (unknown && !options.unknown_passable) {
          EXPECT_EQ(costmap.cost(cell), Costmap::kNoGo);
          EXPECT_FALSE(costmap.Traversable(cell));
          continue;
        }
        const int expected = ExpectedCost(BruteForceDistanceM(grid, cell, 65), options);
        if (expected < 0) continue;
        ASSERT_EQ(costmap.cost(cell), expected) << "seed " << seed << " cell " << col << "," << row;
        EXPECT_EQ(costmap.Traversable(cell), expected < Costmap::kInscribed);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 20000);
}

TEST(CostmapTest, LethalInscribedAndDecayAtKnownDistances) {
  OccupancyGrid grid(41, 5, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  grid.at({0, 2}) = OccupancyGrid::kOccupied;
  CostmapOptions options;  // radius 0.2 + clearance 0.05, inflation 0.4, scale 5
  const Costmap costmap(grid, options);
  auto cost_at = [&](int col) { return static_cast<int>(costmap.cost({col, 2})); };
  EXPECT_EQ(cost_at(0), Costmap::kLethal);
  EXPECT_EQ(cost_at(2), Costmap::kInscribed);  // 0.10 m
  EXPECT_EQ(cost_at(4), Costmap::kInscribed);  // 0.20 m: inside the DWA's safety margin
  EXPECT_EQ(cost_at(5), Costmap::kInscribed);  // 0.25 m: radius + margin itself is inscribed
  EXPECT_EQ(cost_at(6), 196);                  // 0.30 m: 252 e^-0.25 = 196.3
  EXPECT_EQ(cost_at(11), 56);                  // 0.55 m: 252 e^-1.5 = 56.2
  EXPECT_EQ(cost_at(13), 34);                  // 0.65 m (outer edge): 252 e^-2 = 34.1
  EXPECT_EQ(cost_at(14), Costmap::kFree);      // 0.70 m
  EXPECT_EQ(cost_at(40), Costmap::kFree);
  EXPECT_NEAR(costmap.ObstacleDistanceM({3, 2}), 0.15, 1e-6);  // stored as float
  EXPECT_NEAR(costmap.ObstacleDistanceM({3, 4}), std::hypot(3, 2) * kRes, 1e-6);
  EXPECT_FALSE(costmap.Traversable({5, 2}));
  EXPECT_TRUE(costmap.Traversable({6, 2}));
  // Decay is monotone over the band.
  for (int col = 6; col < 14; ++col) EXPECT_GE(cost_at(col), cost_at(col + 1));
}

TEST(CostmapTest, OccupiedThresholdDecidesObstacles) {
  OccupancyGrid grid(9, 3, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  grid.at({2, 1}) = 64;
  grid.at({6, 1}) = 65;
  CostmapOptions options;
  options.robot_radius_m = 0.0;
  options.inflation_margin_m = 0.0;
  const Costmap costmap(grid, options);
  EXPECT_EQ(costmap.cost({2, 1}), Costmap::kFree);
  EXPECT_EQ(costmap.cost({6, 1}), Costmap::kLethal);
  options.occupied_threshold = 64;
  EXPECT_EQ(Costmap(grid, options).cost({2, 1}), Costmap::kLethal);
}

TEST(CostmapTest, UnknownCellsArePassableOrNoGoAndNeverInflate) {
  // Left half unknown, right half free, no obstacles.
  OccupancyGrid grid(20, 6, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 10; ++col) grid.at({col, row}) = OccupancyGrid::kUnknown;
  }
  CostmapOptions options;
  const Costmap passable(grid, options);
  EXPECT_TRUE(std::isinf(passable.ObstacleDistanceM({10, 3})));
  EXPECT_TRUE(passable.IsUnknown({3, 3}));
  EXPECT_FALSE(passable.IsUnknown({10, 3}));
  EXPECT_EQ(passable.cost({3, 3}), Costmap::kFree);  // the penalty is the planner's
  EXPECT_TRUE(passable.Traversable({3, 3}));
  EXPECT_EQ(passable.cost({10, 3}), Costmap::kFree);  // next to unknown, still free

  options.unknown_passable = false;
  const Costmap closed(grid, options);
  EXPECT_EQ(closed.cost({3, 3}), Costmap::kNoGo);
  EXPECT_FALSE(closed.Traversable({9, 3}));
  EXPECT_EQ(closed.cost({10, 3}), Costmap::kFree);

  // An unknown cell near an obstacle gets the obstacle's inflation.
  grid.at({0, 0}) = OccupancyGrid::kOccupied;
  options.unknown_passable = true;
  EXPECT_EQ(Costmap(grid, options).cost({1, 0}), Costmap::kInscribed);
}

TEST(CostmapTest, GeometryAndOffMapCells) {
  const OccupancyGrid grid(7, 4, kRes, {-1.0, 2.0}, OccupancyGrid::kFree);
  const Costmap costmap(grid, CostmapOptions{});
  EXPECT_EQ(costmap.width_cells(), 7);
  EXPECT_EQ(costmap.height_cells(), 4);
  for (const CellIndex cell : {CellIndex{0, 0}, CellIndex{6, 3}, CellIndex{3, 1}}) {
    EXPECT_EQ(costmap.WorldToCell(costmap.CellCenter(cell)), cell);
    EXPECT_EQ(costmap.WorldToCell(grid.CellCenter(cell)), grid.WorldToCell(grid.CellCenter(cell)));
  }
  EXPECT_EQ(costmap.cost({-1, 0}), Costmap::kNoGo);
  EXPECT_EQ(costmap.cost({7, 0}), Costmap::kNoGo);
  EXPECT_FALSE(costmap.Traversable({0, 4}));
  EXPECT_FALSE(costmap.IsUnknown({0, -1}));
  EXPECT_EQ(costmap.ObstacleDistanceM({0, -1}), 0.0);
}

TEST(CostmapTest, RejectsBadOptions) {
  const OccupancyGrid grid(4, 4, kRes, {0.0, 0.0});
  auto build = [&](auto edit) {
    CostmapOptions options;
    edit(options);
    return Costmap(grid, options);
  };
  EXPECT_THROW(build([](CostmapOptions& o) { o.robot_radius_m = -0.1; }), std::invalid_argument);
  EXPECT_THROW(build([](CostmapOptions& o) { o.inflation_margin_m = NAN; }), std::invalid_argument);
  EXPECT_THROW(build([](CostmapOptions& o) { o.cost_scaling_per_m = -1.0; }),
               std::invalid_argument);
  EXPECT_THROW(build([](CostmapOptions& o) { o.occupied_threshold = 0; }), std::invalid_argument);
  EXPECT_THROW(build([](CostmapOptions& o) { o.occupied_threshold = 101; }), std::invalid_argument);
  EXPECT_THROW(build([](CostmapOptions& o) { o.unknown_cost = 253; }), std::invalid_argument);
  EXPECT_NO_THROW(build([](CostmapOptions& o) { o.unknown_cost = 252; }));
}

}  // namespace
}  // namespace aslam
