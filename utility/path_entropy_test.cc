#include "utility/path_entropy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace aslam {
namespace {

// h(0.1) = -0.1 log2 0.1 - 0.9 log2 0.9 = 0.33219 + 0.13681 = 0.4689955935892812
// h(0.45) = -0.45 log2 0.45 - 0.55 log2 0.55 = 0.51840 + 0.47437 = 0.9927744539878083
constexpr double kHUnknown = 0.4689955935892812;
constexpr double kHKnown = 0.9927744539878083;

// A row of cells, 0.1 m each, origin (0, 0): cell c covers x in [0.1 c, 0.1 c + 0.1).
OccupancyGrid Row(int width_cells, int8_t fill) {
  return OccupancyGrid(width_cells, 1, 0.1, {0.0, 0.0}, fill);
}

TEST(CellEntropy, BinaryEntropyInBits) {
  EXPECT_NEAR(CellEntropyBits(0.1), kHUnknown, 1e-15);
  EXPECT_NEAR(CellEntropyBits(0.45), kHKnown, 1e-15);
  EXPECT_DOUBLE_EQ(CellEntropyBits(0.5), 1.0);
  EXPECT_DOUBLE_EQ(CellEntropyBits(0.0), 0.0);
  EXPECT_DOUBLE_EQ(CellEntropyBits(1.0), 0.0);
}

TEST(Bresenham, StraightDiagonalAndSingleCellLines) {
  const auto straight = BresenhamLine({0, 0}, {3, 0});
  ASSERT_EQ(straight.size(), 4u);  // both ends included
  for (int i = 0; i < 4; ++i) EXPECT_EQ(straight[i], (CellIndex{i, 0}));

  const auto diagonal = BresenhamLine({3, 3}, {0, 0});
  ASSERT_EQ(diagonal.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(diagonal[i], (CellIndex{3 - i, 3 - i}));

  const auto single = BresenhamLine({5, -2}, {5, -2});
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0], (CellIndex{5, -2}));
}

TEST(Bresenham, SlopedLineIsEightConnectedWithMaxDeltaPlusOneCells) {
  // (0,0) -> (4,2): K = max(|dx|, |dy|) + 1 = 5; the error term gives
  // (0,0) (1,1) (2,1) (3,2) (4,2): one column per step, rows 0, 1, 1, 2, 2.
  const auto line = BresenhamLine({0, 0}, {4, 2});
  ASSERT_EQ(line.size(), 5u);
  EXPECT_EQ(line.front(), (CellIndex{0, 0}));
  EXPECT_EQ(line.back(), (CellIndex{4, 2}));
  EXPECT_EQ(line[2], (CellIndex{2, 1}));
  for (std::size_t i = 1; i < line.size(); ++i) {
    EXPECT_EQ(line[i].col - line[i - 1].col, 1);
    EXPECT_LE(std::abs(line[i].row - line[i - 1].row), 1);
  }
  // Steep and backwards: one cell per row.
  const auto steep = BresenhamLine({2, 7}, {0, 0});
  ASSERT_EQ(steep.size(), 8u);
  for (std::size_t i = 1; i < steep.size(); ++i) EXPECT_EQ(steep[i].row, steep[i - 1].row - 1);
}

TEST(PathEntropy, AllUnknownRayIsKTimesHOfPointOne) {
  // 5 unknown cells: E = 5 h(0.1) = 2.3449779679464062.
  const RayEntropy ray = PathEntropy(Row(10, OccupancyGrid::kUnknown), {0, 0}, {4, 0}, {});
  EXPECT_EQ(ray.ray_cells, 5);
  EXPECT_EQ(ray.unknown_cells, 5);
  EXPECT_NEAR(ray.entropy_bits, 2.3449779679464062, 1e-12);
}

TEST(PathEntropy, AllKnownRayIsKTimesHOfPointFourFive) {
  // Free and occupied alike are "known": E = 5 h(0.45) = 4.963872269939041.
  OccupancyGrid map = Row(10, OccupancyGrid::kFree);
  map.at({2, 0}) = OccupancyGrid::kOccupied;
  map.at({3, 0}) = 40;  // uncertain but observed
  const RayEntropy ray = PathEntropy(map, {0, 0}, {4, 0}, {});
  EXPECT_EQ(ray.ray_cells, 5);
  EXPECT_EQ(ray.unknown_cells, 0);
  EXPECT_NEAR(ray.entropy_bits, 4.963872269939041, 1e-12);
}

TEST(PathEntropy, HalfKnownHalfUnknown) {
  // Cells 0..2 free, 3..5 unknown: E = 3 h(0.45) + 3 h(0.1) = 4.385310142731269, E/K = 0.7308850.
  OccupancyGrid map = Row(10, OccupancyGrid::kUnknown);
  for (int c = 0; c < 3; ++c) map.at({c, 0}) = OccupancyGrid::kFree;
  const RayEntropy ray = PathEntropy(map, {5, 0}, {0, 0}, {});  // direction does not matter
  EXPECT_EQ(ray.ray_cells, 6);
  EXPECT_EQ(ray.unknown_cells, 3);
  EXPECT_NEAR(ray.entropy_bits, 4.385310142731269, 1e-12);
  EXPECT_NEAR(ray.entropy_bits / ray.ray_cells, 0.7308850237885448, 1e-12);
}

TEST(PathEntropy, CellsOffTheMapCountAsKnown) {
  // A 5-cell unknown row; the ray (2,0) -> (7,0) has cells 2, 3, 4 on the map
  // (unknown) and 5, 6, 7 off it (known): E = 3 h(0.1) + 3 h(0.45) = 4.385310142731269.
  const RayEntropy ray = PathEntropy(Row(5, OccupancyGrid::kUnknown), {2, 0}, {7, 0}, {});
  EXPECT_EQ(ray.ray_cells, 6);
  EXPECT_EQ(ray.unknown_cells, 3);
  EXPECT_NEAR(ray.entropy_bits, 4.385310142731269, 1e-12);
  // Wholly off the map (negative side): all known.
  const RayEntropy off = PathEntropy(Row(5, OccupancyGrid::kUnknown), {-1, -1}, {-4, -1}, {});
  EXPECT_EQ(off.unknown_cells, 0);
  EXPECT_NEAR(off.entropy_bits, 4 * kHKnown, 1e-12);
}

TEST(Beta, DigitsOfTheIntegerPartOfU1) {
  EXPECT_EQ(DigitsOfIntegerPart(0.5), 1);   // U1 < 1
  EXPECT_EQ(DigitsOfIntegerPart(9.99), 1);  // integer part 9
  EXPECT_EQ(DigitsOfIntegerPart(10.0), 2);
  EXPECT_EQ(DigitsOfIntegerPart(123.4), 3);
  EXPECT_EQ(DigitsOfIntegerPart(0.0), 1);
  EXPECT_EQ(DigitsOfIntegerPart(999.999), 3);
  EXPECT_EQ(DigitsOfIntegerPart(1000.0), 4);
  EXPECT_EQ(DigitsOfIntegerPart(1e20), 21);
  EXPECT_EQ(DigitsOfIntegerPart(std::nan("")), 1);
}

TEST(U2, TinyGridWorkedByHand) {
  // Row of 10 cells at 0.1 m: cells 0, 1 free, 2..9 unknown. R = cell 0, n = cell 4, U1 = 12.5.
  //   ray 0..4: K = 5, two known and three unknown cells
  //   E   = 2 h(0.45) + 3 h(0.1) = 1.9855489079756166 + 1.4069867807678436 = 3.39253568874346
  //   E/K = 0.678507137748692
  //   β   = 2 (U1 = 12.5 has two digits), ρ = 100
  //   d   = 4 cells * 0.1 m = 0.4 m; γ = exp(-0.6 * 0.4) = exp(-0.24) = 0.7866278610665535
  //   U2  = (1 - 0.678507137748692) * 100 + 0.7866278610665535 = 32.93591408619736
  //   total (ours) = U1 + U2 = 12.5 + 32.93591408619736 = 45.43591408619736
  OccupancyGrid map = Row(10, OccupancyGrid::kUnknown);
  map.at({0, 0}) = OccupancyGrid::kFree;
  map.at({1, 0}) = OccupancyGrid::kFree;
  const double u1 = 12.5;
  const U2Terms t = ComputeU2(map, {0, 0}, {4, 0}, u1, {});
  EXPECT_EQ(t.ray_cells, 5);
  EXPECT_NEAR(t.path_entropy_bits, 3.39253568874346, 1e-12);
  EXPECT_NEAR(t.mean_entropy_bits, 0.678507137748692, 1e-12);
  EXPECT_DOUBLE_EQ(t.distance_m, 0.4);
  EXPECT_NEAR(t.gamma, 0.7866278610665535, 1e-12);
  EXPECT_EQ(t.beta, 2);
  EXPECT_DOUBLE_EQ(t.rho, 100.0);
  EXPECT_NEAR(t.u2, 32.93591408619736, 1e-10);
  EXPECT_NEAR(u1 + t.u2, 45.43591408619736, 1e-10);

  // The authors' unit: d = 4 cells, γ = exp(-2.4) = 0.09071795328941251,
  // U2 = 32.149286225130800 + 0.09071795328941251 = 32.240004178420214.
  PathEntropyOptions cells;
  cells.distance_unit = DistanceUnit::kCells;
  const U2Terms c = ComputeU2(map, {0, 0}, {4, 0}, u1, cells);
  EXPECT_NEAR(c.gamma, 0.09071795328941251, 1e-12);
  EXPECT_DOUBLE_EQ(c.distance_m, 0.4);  // reported in metres either way
  EXPECT_NEAR(c.u2, 32.240004178420214, 1e-10);

  // ρ follows U1's digits: U1 = 123.4 -> β = 3, ρ = 1000, U2 = 321.492862251308 + γ.
  const U2Terms big = ComputeU2(map, {0, 0}, {4, 0}, 123.4, {});
  EXPECT_DOUBLE_EQ(big.rho, 1000.0);
  EXPECT_NEAR(big.u2, 321.492862251308 + 0.7866278610665535, 1e-9);
}

TEST(U2, RobotOnTheTargetCell) {
  // K = 1 (R itself), d = 0: γ = 1; a known cell gives U2 = (1 - h(0.45)) * 10 + 1.
  const U2Terms t = ComputeU2(Row(3, OccupancyGrid::kFree), {1, 0}, {1, 0}, 0.0, {});
  EXPECT_EQ(t.ray_cells, 1);
  EXPECT_DOUBLE_EQ(t.gamma, 1.0);
  EXPECT_NEAR(t.u2, (1.0 - kHKnown) * 10.0 + 1.0, 1e-12);
}

TEST(PathEntropyOptions, ValidateNamesTheField) {
  PathEntropyOptions options;
  options.lambda = -1.0;
  try {
    options.Validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lambda"), std::string::npos);
  }
  options = {};
  options.p_unknown = 1.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace aslam
