#include "utility/unknown_pockets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace aslam {
namespace {

constexpr double kRes = 0.1;

void Fill(OccupancyGrid* map, int col0, int row0, int col1, int row1, int8_t value) {
  for (int r = row0; r <= row1; ++r) {
    for (int c = col0; c <= col1; ++c) map->at({c, r}) = value;
  }
}

Frontier FrontierAt(const std::vector<CellIndex>& cells) {
  Frontier f;
  for (const CellIndex& c : cells) {
    f.points_m.push_back({(c.col + 0.5) * kRes, (c.row + 0.5) * kRes});
  }
  f.target_m = f.points_m.front();
  return f;
}

// 6 m x 4 m: free west of a wall at column 30, unknown east of it up to the map's edge; an
// unknown 1 m x 1 m square (cols 8..17, rows 8..17) in the free part; the wall's openings
// are the test's.
OccupancyGrid RoomBesideTheUnknown() {
  OccupancyGrid map(60, 40, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  Fill(&map, 31, 0, 59, 39, OccupancyGrid::kUnknown);
  Fill(&map, 30, 0, 30, 39, OccupancyGrid::kOccupied);
  Fill(&map, 8, 8, 17, 17, OccupancyGrid::kUnknown);
  return map;
}

std::vector<double> Areas(const OccupancyGrid& map, const std::vector<Frontier>& frontiers,
                          double cap_m2) {
  return BorderedUnknownAreasM2(map, Costmap(map, CostmapOptions{}), frontiers, cap_m2);
}

TEST(UnknownPockets, AnEnclosedRegionIsMeasuredAndALargeOrUnboundedOneIsOpen) {
  OccupancyGrid map = RoomBesideTheUnknown();
  Fill(&map, 30, 15, 30, 24, OccupancyGrid::kUnknown);  // a 1 m door in the wall
  const Frontier beside_square = FrontierAt({{7, 10}, {7, 11}, {7, 12}});
  const Frontier in_the_door = FrontierAt({{29, 18}, {29, 19}, {29, 20}});
  const Frontier touching_nothing = FrontierAt({{3, 30}});
  const std::vector<double> areas = Areas(map, {beside_square, in_the_door, touching_nothing}, 4.0);
  ASSERT_EQ(areas.size(), 3u);
  EXPECT_NEAR(areas[0], 100 * kRes * kRes, 1e-9);  // the square, every cell of it
  EXPECT_TRUE(std::isinf(areas[1]));               // through the door to the map's edge
  EXPECT_EQ(areas[2], 0.0);
  // The square is open against a cap below its area.
  EXPECT_TRUE(std::isinf(Areas(map, {beside_square}, 0.99)[0]));
  EXPECT_NEAR(Areas(map, {beside_square}, 1.01)[0], 1.0, 1e-9);
}

TEST(UnknownPockets, AGapTheRobotCannotPassLeadsNowhere) {
  OccupancyGrid map = RoomBesideTheUnknown();
  Fill(&map, 30, 18, 30, 20, OccupancyGrid::kUnknown);  // 0.3 m: inscribed for a 0.2 m robot
  Fill(&map, 30, 5, 30, 12, OccupancyGrid::kUnknown);   // 0.8 m: passable
  const Frontier at_the_gap = FrontierAt({{29, 17}, {29, 18}, {29, 19}, {29, 20}, {29, 21}});
  const Frontier at_the_door = FrontierAt({{29, 6}, {29, 8}, {29, 10}});
  const std::vector<double> areas = Areas(map, {at_the_gap, at_the_door}, 4.0);
  EXPECT_EQ(areas[0], 0.0);
  EXPECT_TRUE(std::isinf(areas[1]));
}

TEST(UnknownPockets, EveryFrontierOfARegionGetsItsWholeArea) {
  const OccupancyGrid map = RoomBesideTheUnknown();
  const std::vector<double> areas =
      Areas(map, {FrontierAt({{7, 12}}), FrontierAt({{18, 12}}), FrontierAt({{12, 18}})}, 4.0);
  for (double area : areas) EXPECT_NEAR(area, 1.0, 1e-9);
}

}  // namespace
}  // namespace aslam
