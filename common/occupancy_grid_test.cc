#include "common/occupancy_grid.h"

#include <gtest/gtest.h>

namespace aslam {
namespace {

TEST(OccupancyGrid, WorldToCellUsesLowerLeftOrigin) {
  const OccupancyGrid grid(10, 5, 0.5, {-1.0, 2.0});
  EXPECT_EQ(grid.WorldToCell({-1.0, 2.0}), (CellIndex{0, 0}));
  EXPECT_EQ(grid.WorldToCell({-0.51, 2.49}), (CellIndex{0, 0}));
  EXPECT_EQ(grid.WorldToCell({-0.5, 2.5}), (CellIndex{1, 1}));
  EXPECT_EQ(grid.WorldToCell({-1.01, 1.99}), (CellIndex{-1, -1}));
  EXPECT_FALSE(grid.Contains(grid.WorldToCell({-1.01, 2.0})));
  EXPECT_FALSE(grid.Contains(grid.WorldToCell({4.0, 2.0})));  // x = origin + width is outside
  EXPECT_TRUE(grid.Contains(grid.WorldToCell({3.99, 4.49})));
}

TEST(OccupancyGrid, CellCenterRoundTrips) {
  const OccupancyGrid grid(40, 30, 0.05, {2.0, -3.0});
  for (int row = 0; row < grid.height_cells(); ++row) {
    for (int col = 0; col < grid.width_cells(); ++col) {
      EXPECT_EQ(grid.WorldToCell(grid.CellCenter({col, row})), (CellIndex{col, row}));
    }
  }
  const Point2d c = grid.CellCenter({3, 4});
  EXPECT_DOUBLE_EQ(c.x_m, 2.0 + 3.5 * 0.05);
  EXPECT_DOUBLE_EQ(c.y_m, -3.0 + 4.5 * 0.05);
}

TEST(OccupancyGrid, RowMajorStorageAndCounts) {
  OccupancyGrid grid(4, 3, 1.0, {0.0, 0.0});
  EXPECT_EQ(grid.cells().size(), 12u);
  grid.at({1, 2}) = 0;
  grid.at({3, 0}) = 100;
  grid.at({0, 1}) = 42;
  EXPECT_EQ(grid.cells()[2 * 4 + 1], 0);
  EXPECT_EQ(grid.cells()[3], 100);
  EXPECT_EQ(grid.ValueOr({-1, 0}, 77), 77);
  const CellIndex back = grid.CellOfLinearIndex(grid.LinearIndex({1, 2}));
  EXPECT_EQ(back.col, 1);
  EXPECT_EQ(back.row, 2);
  const auto counts = grid.CountCells();
  EXPECT_EQ(counts.unknown, 9u);
  EXPECT_EQ(counts.free, 1u);
  EXPECT_EQ(counts.occupied, 2u);
}

}  // namespace
}  // namespace aslam
