#include "navigation/costmap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
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

// The documented cost of a cell at obstacle distance d (centre to centre; its clearance is
// half a cell less), or -1 when the clearance is too close to a band edge or a rounding tie
// for float rounding to be decisive.
int ExpectedCost(double d, const CostmapOptions& o) {
  const double radius = o.robot_radius_m + o.clearance_margin_m;
  const double outer = radius + o.inflation_margin_m;
  if (d == 0.0) return Costmap::kLethal;
  const double clearance = d - 0.5 * kRes;
  if (std::abs(clearance - radius) < 1e-6 || std::abs(clearance - outer) < 1e-6) return -1;
  if (clearance < radius) return Costmap::kInscribed;
  if (clearance > outer) return Costmap::kFree;
  const double value = 252.0 * std::exp(-o.cost_scaling_per_m * (clearance - radius));
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
  // Centre distances; the clearance (to the obstacle cell's edge) is 0.025 m less.
  EXPECT_EQ(cost_at(2), Costmap::kInscribed);  // 0.10 m
  EXPECT_EQ(cost_at(4), Costmap::kInscribed);  // 0.20 m: inside the DWA's safety margin
  EXPECT_EQ(cost_at(5), Costmap::kInscribed);  // 0.25 m: clearance 0.225 m, inside it too
  EXPECT_EQ(cost_at(6), 222);                  // 0.30 m: 252 e^-0.125 = 222.4
  EXPECT_EQ(cost_at(11), 64);                  // 0.55 m: 252 e^-1.375 = 63.7
  EXPECT_EQ(cost_at(13), 39);                  // 0.65 m (outer edge 0.675): 252 e^-1.875 = 38.7
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

// --- Incremental updates ---

float OuterBandM(const CostmapOptions& o) {
  return static_cast<float>(o.robot_radius_m + o.clearance_margin_m + o.inflation_margin_m);
}

// Every cell of `updated` against a fresh costmap of `grid`: costs, traversability
// and unknown status identical; distances identical within the cost band and
// beyond it on both sides otherwise (the documented ObstacleDistanceM contract).
void ExpectSameAsFresh(const Costmap& updated, const OccupancyGrid& grid,
                       const CostmapOptions& options, const std::string& where) {
  const Costmap fresh(grid, options);
  ASSERT_EQ(updated.width_cells(), fresh.width_cells()) << where;
  ASSERT_EQ(updated.height_cells(), fresh.height_cells()) << where;
  ASSERT_EQ(updated.resolution_m(), fresh.resolution_m()) << where;
  ASSERT_EQ(updated.origin_m().x_m, fresh.origin_m().x_m) << where;
  ASSERT_EQ(updated.origin_m().y_m, fresh.origin_m().y_m) << where;
  const float outer_m = OuterBandM(options);
  for (int row = 0; row < grid.height_cells(); ++row) {
    for (int col = 0; col < grid.width_cells(); ++col) {
      const CellIndex cell{col, row};
      ASSERT_EQ(static_cast<int>(updated.cost(cell)), static_cast<int>(fresh.cost(cell)))
          << where << " cell " << col << "," << row << " fresh distance "
          << fresh.ObstacleDistanceM(cell) << " updated distance "
          << updated.ObstacleDistanceM(cell);
      ASSERT_EQ(updated.Traversable(cell), fresh.Traversable(cell)) << where;
      ASSERT_EQ(updated.IsUnknown(cell), fresh.IsUnknown(cell)) << where;
      const float fresh_m = static_cast<float>(fresh.ObstacleDistanceM(cell));
      const float updated_m = static_cast<float>(updated.ObstacleDistanceM(cell));
      if (fresh_m <= outer_m) {
        ASSERT_EQ(updated_m, fresh_m) << where << " cell " << col << "," << row;
      } else {
        ASSERT_GT(updated_m, outer_m) << where << " cell " << col << "," << row;
      }
    }
  }
  // The raw layers the planner reads, whole.
  ASSERT_TRUE(updated.costs() == fresh.costs()) << where;
  ASSERT_TRUE(updated.unknown_mask() == fresh.unknown_mask()) << where;
}

// Option sets that move the band, the decay, the threshold and the unknown rule.
std::vector<CostmapOptions> UpdateOptionSets() {
  std::vector<CostmapOptions> sets(6);
  sets[1].robot_radius_m = 0.0;
  sets[1].clearance_margin_m = 0.0;
  sets[1].inflation_margin_m = 0.0;  // band of one cell: lethal or free
  sets[2].unknown_passable = false;
  sets[2].occupied_threshold = 50;
  sets[3].robot_radius_m = 0.33;
  sets[3].inflation_margin_m = 1.1;  // a wide band (36 cells)
  sets[3].cost_scaling_per_m = 1.5;
  sets[4].robot_radius_m = 0.12;
  sets[4].clearance_margin_m = 0.03;  // radius + margin on a cell boundary
  sets[4].inflation_margin_m = 0.2;
  sets[4].cost_scaling_per_m = 0.0;
  sets[4].unknown_passable = false;
  sets[5].occupied_threshold = 100;
  sets[5].inflation_margin_m = 0.55;
  return sets;
}

int8_t RandomValue(std::mt19937& rng, int kind) {  // 0 free, 1 obstacle, 2 unknown
  if (kind == 2) return OccupancyGrid::kUnknown;
  if (kind == 1) return static_cast<int8_t>(std::uniform_int_distribution<int>(65, 100)(rng));
  return static_cast<int8_t>(std::uniform_int_distribution<int>(0, 49)(rng));
}

// One random edit, mostly local the way SLAM maps and scan marks change.
void RandomEdit(std::mt19937& rng, OccupancyGrid* grid, int threshold, std::string* what) {
  const int width = grid->width_cells();
  const int height = grid->height_cells();
  std::uniform_int_distribution<int> kind_of(0, 7);
  std::uniform_int_distribution<int> col_of(0, width - 1);
  std::uniform_int_distribution<int> row_of(0, height - 1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int kind = kind_of(rng);
  const CellIndex centre{col_of(rng), row_of(rng)};
  const int radius = std::uniform_int_distribution<int>(0, 9)(rng);
  auto blob = [&](auto edit) {
    for (int dr = -radius; dr <= radius; ++dr) {
      for (int dc = -radius; dc <= radius; ++dc) {
        const CellIndex cell{centre.col + dc, centre.row + dr};
        if (grid->Contains(cell) && dc * dc + dr * dr <= radius * radius && u01(rng) < 0.7) {
          edit(grid->at(cell));
        }
      }
    }
  };
  switch (kind) {
    case 0:
      *what = "new obstacles";
      blob([&](int8_t& v) { v = RandomValue(rng, 1); });
      break;
    case 1:
      *what = "new free cells";
      blob([&](int8_t& v) { v = RandomValue(rng, 0); });
      break;
    case 2:
      *what = "new unknown cells";
      blob([&](int8_t& v) { v = RandomValue(rng, 2); });
      break;
    case 3:
      *what = "obstacles removed";
      blob([&](int8_t& v) {
        if (v >= threshold) v = RandomValue(rng, u01(rng) < 0.5 ? 0 : 2);
      });
      break;
    case 4:
      *what = "unknown revealed";
      blob([&](int8_t& v) {
        if (v < 0) v = RandomValue(rng, u01(rng) < 0.8 ? 0 : 1);
      });
      break;
    case 5:
      *what = "a mixed blob";
      blob([&](int8_t& v) { v = RandomValue(rng, std::uniform_int_distribution<int>(0, 2)(rng)); });
      break;
    case 6: {
      *what = "scattered cells";
      const int count = std::uniform_int_distribution<int>(1, 12)(rng);
      for (int i = 0; i < count; ++i) {
        grid->at({col_of(rng), row_of(rng)}) =
            RandomValue(rng, std::uniform_int_distribution<int>(0, 2)(rng));
      }
      break;
    }
    default: {
      *what = "a wall segment";
      const bool horizontal = u01(rng) < 0.5;
      const int length = std::uniform_int_distribution<int>(5, 60)(rng);
      const int8_t value = RandomValue(rng, u01(rng) < 0.7 ? 1 : 0);
      for (int i = 0; i < length; ++i) {
        const CellIndex cell = horizontal ? CellIndex{centre.col + i, centre.row}
                                          : CellIndex{centre.col, centre.row + i};
        if (grid->Contains(cell)) grid->at(cell) = value;
      }
    }
  }
}

TEST(CostmapUpdateTest, RandomEditSequencesMatchFreshCostmaps) {
  const std::vector<CostmapOptions> option_sets = UpdateOptionSets();
  int incremental = 0;
  int full = 0;
  int unchanged = 0;
  for (std::size_t set = 0; set < option_sets.size(); ++set) {
    const CostmapOptions& options = option_sets[set];
    for (int run = 0; run < 4; ++run) {
      std::mt19937 rng(static_cast<unsigned>(100 * set + run));
      const int width = std::uniform_int_distribution<int>(40, 190)(rng);
      const int height = std::uniform_int_distribution<int>(30, 150)(rng);
      OccupancyGrid grid = RandomGrid(rng, width, height, 0.01 + 0.01 * run, 0.15 + 0.1 * run);
      Costmap costmap(grid, options);
      for (int step = 0; step < 40; ++step) {
        std::string what;
        if (step % 15 == 14) {
          what = "a whole new map";
          grid = RandomGrid(rng, width, height, 0.005 + 0.01 * (step % 4), 0.3);
        } else {
          RandomEdit(rng, &grid, options.occupied_threshold, &what);
          if (step % 3 == 0) RandomEdit(rng, &grid, options.occupied_threshold, &what);
        }
        switch (costmap.Update(grid, options)) {
          case Costmap::UpdateKind::kIncremental: ++incremental; break;
          case Costmap::UpdateKind::kFull: ++full; break;
          case Costmap::UpdateKind::kUnchanged: ++unchanged; break;
        }
        ExpectSameAsFresh(costmap, grid, options,
                          "set " + std::to_string(set) + " run " + std::to_string(run) + " step " +
                              std::to_string(step) + " after " + what);
        if (HasFatalFailure()) return;
      }
    }
  }
  // The sequences exercise every path, mostly the incremental one.
  EXPECT_GT(incremental, 500);
  EXPECT_GT(full, 20);
  EXPECT_GT(unchanged, 0);
}

// A large map with walls (widths where float rounding in the transform
// matters most), many small local edits.
TEST(CostmapUpdateTest, LargeMapLocalEditsMatchFreshCostmaps) {
  std::mt19937 rng(7);
  OccupancyGrid grid(1500, 900, kRes, {-3.0, 2.0}, OccupancyGrid::kFree);
  std::uniform_int_distribution<int> col_of(0, 1499);
  std::uniform_int_distribution<int> row_of(0, 899);
  for (int wall = 0; wall < 150; ++wall) {
    const CellIndex start{col_of(rng), row_of(rng)};
    const bool horizontal = wall % 2 == 0;
    for (int i = 0; i < 400; ++i) {
      const CellIndex cell =
          horizontal ? CellIndex{start.col + i, start.row} : CellIndex{start.col, start.row + i};
      if (grid.Contains(cell)) grid.at(cell) = OccupancyGrid::kOccupied;
    }
  }
  for (int i = 0; i < 200; ++i) grid.at({col_of(rng), row_of(rng)}) = OccupancyGrid::kOccupied;
  CostmapOptions options;
  options.unknown_passable = false;
  Costmap costmap(grid, options);
  for (int step = 0; step < 25; ++step) {
    std::string what;
    RandomEdit(rng, &grid, options.occupied_threshold, &what);
    EXPECT_NE(costmap.Update(grid, options), Costmap::UpdateKind::kFull) << what;
    ExpectSameAsFresh(costmap, grid, options, "step " + std::to_string(step) + " after " + what);
    if (HasFatalFailure()) return;
  }
}

TEST(CostmapUpdateTest, UnchangedMapIsANoOp) {
  std::mt19937 rng(3);
  OccupancyGrid grid = RandomGrid(rng, 50, 40, 0.03, 0.2);
  for (const CostmapOptions& options : UpdateOptionSets()) {
    Costmap costmap(grid, options);
    const std::vector<uint8_t> costs = costmap.costs();
    EXPECT_EQ(costmap.Update(grid, options), Costmap::UpdateKind::kUnchanged);
    EXPECT_EQ(costmap.costs(), costs);
    // Values that keep every cell's status (free stays free, obstacle stays obstacle).
    OccupancyGrid same_status = grid;
    for (int8_t& value : same_status.mutable_cells()) {
      if (value >= 0 && value < options.occupied_threshold) value = 0;
      if (value >= options.occupied_threshold) value = 100;
    }
    EXPECT_EQ(costmap.Update(same_status, options), Costmap::UpdateKind::kUnchanged);
    EXPECT_EQ(costmap.costs(), costs);
    ExpectSameAsFresh(costmap, same_status, options, "same status");
  }
}

TEST(CostmapUpdateTest, GeometryOrOptionChangesRebuild) {
  std::mt19937 rng(11);
  const OccupancyGrid grid = RandomGrid(rng, 60, 50, 0.03, 0.2);
  CostmapOptions options;
  Costmap costmap(grid, options);
  // Another origin that does not contain the old grid at a whole-cell offset.
  OccupancyGrid shifted(60, 50, kRes, {-0.3 + 0.5 * kRes, 0.7});
  shifted.mutable_cells() = grid.cells();
  EXPECT_EQ(costmap.Update(shifted, options), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(costmap, shifted, options, "half-cell shift");
  // Smaller; another resolution; other options; empty.
  const OccupancyGrid smaller = RandomGrid(rng, 30, 50, 0.03, 0.2);
  EXPECT_EQ(costmap.Update(smaller, options), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(costmap, smaller, options, "smaller");
  OccupancyGrid coarser(30, 50, 0.1, {-0.3, 0.7});
  coarser.mutable_cells() = smaller.cells();
  EXPECT_EQ(costmap.Update(coarser, options), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(costmap, coarser, options, "coarser");
  CostmapOptions wider = options;
  wider.inflation_margin_m = 0.8;
  EXPECT_EQ(costmap.Update(coarser, wider), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(costmap, coarser, wider, "other options");
  EXPECT_EQ(costmap.Update(OccupancyGrid(), wider), Costmap::UpdateKind::kFull);
  EXPECT_EQ(costmap.width_cells(), 0);
  EXPECT_TRUE(costmap.costs().empty());
  EXPECT_EQ(costmap.Update(grid, wider), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(costmap, grid, wider, "after empty");
  // Bad options still throw.
  CostmapOptions bad = options;
  bad.robot_radius_m = -1.0;
  EXPECT_THROW(costmap.Update(grid, bad), std::invalid_argument);
  // Over 2000 cells on a side (float rounding in the transform): always rebuilt.
  OccupancyGrid long_map(2001, 8, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  Costmap long_costmap(long_map, options);
  long_map.at({1000, 4}) = OccupancyGrid::kOccupied;
  EXPECT_EQ(long_costmap.Update(long_map, options), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(long_costmap, long_map, options, "long map");
  // A default-constructed costmap builds from scratch.
  Costmap empty;
  EXPECT_EQ(empty.Update(grid, options), Costmap::UpdateKind::kFull);
  ExpectSameAsFresh(empty, grid, options, "from default");
}

// The occupancy mapper grows its grid by whole cells on any side, keeping the
// old cells in place: the update keeps the old layers and fills in the rest.
TEST(CostmapUpdateTest, GrownMapIsIncrementalAndMatchesFresh) {
  for (const CostmapOptions& options : UpdateOptionSets()) {
    std::mt19937 rng(options.occupied_threshold +
                     static_cast<int>(options.inflation_margin_m * 10));
    OccupancyGrid grid = RandomGrid(rng, 300, 200, 0.01, 0.3);
    Costmap costmap(grid, options);
    int incremental = 0;
    for (int step = 0; step < 4; ++step) {
      const int left = std::uniform_int_distribution<int>(0, 1)(rng) * 40;
      const int bottom = std::uniform_int_distribution<int>(0, 1)(rng) * 40;
      const int right = std::uniform_int_distribution<int>(0, 1)(rng) * 40;
      const int top =
          (left + bottom + right == 0) ? 40 : std::uniform_int_distribution<int>(0, 1)(rng) * 40;
      OccupancyGrid grown(grid.width_cells() + left + right, grid.height_cells() + bottom + top,
                          kRes,
                          {grid.origin_m().x_m - left * kRes, grid.origin_m().y_m - bottom * kRes});
      for (int row = 0; row < grid.height_cells(); ++row) {
        for (int col = 0; col < grid.width_cells(); ++col) {
          grown.at({col + left, row + bottom}) = grid.at({col, row});
        }
      }
      // Scans near the old border, reaching into the new cells.
      std::string what;
      for (int edit = 0; edit < 3; ++edit) {
        RandomEdit(rng, &grown, options.occupied_threshold, &what);
      }
      grid = grown;
      incremental += costmap.Update(grid, options) == Costmap::UpdateKind::kIncremental;
      ExpectSameAsFresh(costmap, grid, options, "growth step " + std::to_string(step));
      if (HasFatalFailure()) return;
    }
    EXPECT_GE(incremental, 3);  // a ring grown on every side of a small map may not pay off
  }
}

// Obstacles near the old border see into the grown cells: exactly the ring the update recomputes.
TEST(CostmapUpdateTest, GrowthNextToABorderObstacle) {
  OccupancyGrid grid(400, 300, kRes, {1.0, 1.0}, OccupancyGrid::kFree);
  grid.at({0, 10}) = OccupancyGrid::kOccupied;
  grid.at({399, 0}) = OccupancyGrid::kOccupied;
  CostmapOptions options;
  Costmap costmap(grid, options);
  // Grown by 40 cells left and 30 below, all unknown there.
  OccupancyGrid grown(440, 330, kRes, {1.0 - 40 * kRes, 1.0 - 30 * kRes});
  for (int row = 0; row < 300; ++row) {
    for (int col = 0; col < 400; ++col) grown.at({col + 40, row + 30}) = grid.at({col, row});
  }
  EXPECT_EQ(costmap.Update(grown, options), Costmap::UpdateKind::kIncremental);
  ExpectSameAsFresh(costmap, grown, options, "grown");
  EXPECT_EQ(costmap.cost({39, 40}), Costmap::kInscribed);   // new, left of the first obstacle
  EXPECT_EQ(costmap.cost({439, 29}), Costmap::kInscribed);  // new, below the second
}

TEST(CostmapUpdateTest, LocalChangeIsIncrementalAndRemovalsClearInflation) {
  OccupancyGrid grid(200, 150, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int col = 0; col < 200; ++col) grid.at({col, 0}) = OccupancyGrid::kOccupied;
  CostmapOptions options;
  Costmap costmap(grid, options);
  grid.at({100, 75}) = OccupancyGrid::kOccupied;
  EXPECT_EQ(costmap.Update(grid, options), Costmap::UpdateKind::kIncremental);
  EXPECT_EQ(costmap.cost({100, 75}), Costmap::kLethal);
  EXPECT_EQ(costmap.cost({103, 75}), Costmap::kInscribed);
  ExpectSameAsFresh(costmap, grid, options, "added");
  grid.at({100, 75}) = OccupancyGrid::kFree;
  EXPECT_EQ(costmap.Update(grid, options), Costmap::UpdateKind::kIncremental);
  EXPECT_EQ(costmap.cost({103, 75}), Costmap::kFree);
  ExpectSameAsFresh(costmap, grid, options, "removed");
  // Unknown status alone: no distance work, and the cell reads unknown.
  grid.at({50, 50}) = OccupancyGrid::kUnknown;
  EXPECT_EQ(costmap.Update(grid, options), Costmap::UpdateKind::kIncremental);
  EXPECT_TRUE(costmap.IsUnknown({50, 50}));
  ExpectSameAsFresh(costmap, grid, options, "unknown");
}

}  // namespace
}  // namespace aslam

namespace aslam {
namespace {

TEST(PlanningObstaclesTest, MarkTheirCellsOccupiedUnlessOffTheMapOrStale) {
  const OccupancyGrid map(20, 10, 0.1, {-1.0, 0.0}, OccupancyGrid::kUnknown);
  const PlanningObstacles obstacles{5'000'000, {{0.05, 0.25}, {-0.95, 0.95}, {3.0, 0.5}}};
  const std::optional<OccupancyGrid> marked = WithPlanningObstacles(map, obstacles, 15'000'000);
  ASSERT_TRUE(marked.has_value());
  int occupied = 0;
  for (int8_t cell : marked->cells()) occupied += cell == OccupancyGrid::kOccupied;
  EXPECT_EQ(occupied, 2);  // (3.0, 0.5) is off the map
  EXPECT_EQ(marked->at({10, 2}), OccupancyGrid::kOccupied);
  EXPECT_EQ(marked->at({0, 9}), OccupancyGrid::kOccupied);
  EXPECT_EQ(marked->at({10, 3}), OccupancyGrid::kUnknown);
  // More than 10 s old, or none: nothing to mark.
  EXPECT_FALSE(WithPlanningObstacles(map, obstacles, 15'000'001).has_value());
  EXPECT_FALSE(WithPlanningObstacles(map, PlanningObstacles{15'000'000, {}}, 15'000'000));
}

}  // namespace
}  // namespace aslam
