#include "frontier/frontier_extractor.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/world_file.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"

namespace aslam {
namespace {

constexpr double kRes = 0.05;
constexpr int8_t kU = OccupancyGrid::kUnknown;
constexpr int8_t kF = OccupancyGrid::kFree;
constexpr int8_t kO = OccupancyGrid::kOccupied;

// Sets cells col0..col1 x row0..row1 (inclusive) to `value`.
void Fill(OccupancyGrid* grid, int col0, int row0, int col1, int row1, int8_t value) {
  for (int row = row0; row <= row1; ++row) {
    for (int col = col0; col <= col1; ++col) grid->at({col, row}) = value;
  }
}

// A walled room, free inside cols 12..47 x rows 12..47 (1.8 m square),
// walls 2 cells thick around it, unknown outside (60 x 60 cells, 3 m).
OccupancyGrid Room() {
  OccupancyGrid grid(60, 60, kRes, {0.0, 0.0}, kU);
  Fill(&grid, 10, 10, 49, 49, kO);
  Fill(&grid, 12, 12, 47, 47, kF);
  return grid;
}
// A doorway in the east wall (cols 48..49), rows row0..row1.
void EastDoor(OccupancyGrid* grid, int row0, int row1) { Fill(grid, 48, row0, 49, row1, kF); }
// A doorway in the north wall (rows 48..49), cols col0..col1.
void NorthDoor(OccupancyGrid* grid, int col0, int col1) { Fill(grid, col0, 48, col1, 49, kF); }
// A doorway in the west wall (cols 10..11), rows row0..row1.
void WestDoor(OccupancyGrid* grid, int row0, int row1) { Fill(grid, 10, row0, 11, row1, kF); }

const Point2d kRoomCentre{1.5, 1.5};

double Distance(Point2d a, Point2d b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

// Every target is traversable in the navigator's costmap and reached by a
// GlobalPlanner search from the robot.
void ExpectTargetsReachable(const OccupancyGrid& map, Point2d robot_m,
                            const std::vector<Frontier>& frontiers) {
  const Costmap costmap(map, CostmapOptions{});
  const ShortestPathTree tree = GlobalPlanner().Search(costmap, costmap.WorldToCell(robot_m));
  for (const Frontier& f : frontiers) {
    const CellIndex target = costmap.WorldToCell(f.target_m);
    EXPECT_TRUE(costmap.Traversable(target)) << "frontier " << f.id;
    EXPECT_TRUE(tree.Reachable(target)) << "frontier " << f.id;
    EXPECT_EQ(map.at(target), kF) << "frontier " << f.id;
  }
}

TEST(FindFrontiers, RoomWithOneDoorwayGivesOneFrontierOfTheDoorwayWidth) {
  OccupancyGrid map = Room();
  EastDoor(&map, 25, 35);  // 11 cells, 0.55 m
  FrontierExtractionStats stats;
  const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, {}, &stats);
  ASSERT_EQ(frontiers.size(), 1u);
  const Frontier& f = frontiers[0];
  // Only the door's outer column touches the unknown; the inner one sees wall diagonally.
  EXPECT_EQ(f.size_cells(), 11);
  ASSERT_EQ(f.cells.size(), 11u);
  for (const CellIndex& cell : f.cells) {
    EXPECT_EQ(cell.col, 49);
    EXPECT_GE(cell.row, 25);
    EXPECT_LE(cell.row, 35);
  }
  EXPECT_NEAR(f.centroid_m.x_m, 49.5 * kRes, 1e-12);
  EXPECT_NEAR(f.centroid_m.y_m, 30.5 * kRes, 1e-12);
  // The middle door cell is 0.25 m from both jambs (> robot radius) but has no room to stand
  // (0.2 + 0.05 + 0.15 m to a cell's edge, 8.5 cells centre to centre): the target steps back
  // into the room, to the first cell of the door's row that far from the jambs' corners (48, 24)
  // and (48, 36): 48 - col >= sqrt(8.5^2 - 6^2) = 6.02, col 41.
  EXPECT_NEAR(f.target_m.x_m, 41.5 * kRes, 1e-12);
  EXPECT_NEAR(f.target_m.y_m, 30.5 * kRes, 1e-12);
  // Asked for no room, the middle door cell is the target.
  FrontierOptions pressed;
  pressed.target_clearance_m = 0.0;
  const std::vector<Frontier> at_the_door = FindFrontiers(map, kRoomCentre, pressed);
  ASSERT_EQ(at_the_door.size(), 1u);
  EXPECT_NEAR(at_the_door[0].target_m.x_m, 49.5 * kRes, 1e-12);
  EXPECT_NEAR(at_the_door[0].target_m.y_m, 30.5 * kRes, 1e-12);
  EXPECT_EQ(f.id, -1);  // FindFrontiers leaves ids to AssignFrontierIds
  EXPECT_EQ(stats.frontier_cells, 11);
  EXPECT_EQ(stats.clusters, 1);
  EXPECT_EQ(stats.segments, 1);
  EXPECT_FALSE(stats.used_planner_search);
  ExpectTargetsReachable(map, kRoomCentre, frontiers);
}

TEST(FindFrontiers, TwoSeparateOpeningsGiveTwoFrontiers) {
  OccupancyGrid map = Room();
  EastDoor(&map, 20, 33);   // 14 cells
  NorthDoor(&map, 15, 26);  // 12 cells
  for (const double target_clearance_m : {0.0, 0.15}) {
    FrontierOptions options;
    options.target_clearance_m = target_clearance_m;
    const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, options);
    ASSERT_EQ(frontiers.size(), 2u);
    std::vector<int> sizes = {frontiers[0].size_cells(), frontiers[1].size_cells()};
    std::sort(sizes.begin(), sizes.end());
    EXPECT_EQ(sizes, (std::vector<int>{12, 14}));
    for (const Frontier& f : frontiers) {
      const bool east = f.size_cells() == 14;
      EXPECT_NEAR(east ? f.centroid_m.x_m : f.centroid_m.y_m, 49.5 * kRes, 1e-12);
      EXPECT_NEAR(east ? f.centroid_m.y_m : f.centroid_m.x_m, (east ? 27.0 : 21.0) * kRes, 1e-12);
      if (target_clearance_m == 0.0) {
        EXPECT_LT(Distance(f.target_m, f.centroid_m), 0.05);  // in the doorway
      } else {
        // In the room, in front of its doorway: the doorways (0.6 and 0.7 m) have no room.
        EXPECT_LT(east ? f.target_m.x_m : f.target_m.y_m, 47.5 * kRes);
        EXPECT_GT(Distance(f.target_m, f.centroid_m), 0.3);
        EXPECT_LE(Distance(f.target_m, f.centroid_m), options.target_radius_m);
      }
    }
    ExpectTargetsReachable(map, kRoomCentre, frontiers);
  }
}

TEST(FindFrontiers, LongOpenSideIsSplitIntoCeilLengthOverMaxSegments) {
  // Free cols 12..49 x rows 12..131 (6 m tall), walls west, south and north,
  // the east side open to the unknown: a straight frontier of 120 cells at col 49.
  OccupancyGrid map(60, 150, kRes, {0.0, 0.0}, kU);
  Fill(&map, 10, 10, 49, 133, kO);
  Fill(&map, 12, 12, 49, 131, kF);
  const Point2d robot{1.0, 3.6};
  FrontierExtractionStats stats;
  const std::vector<Frontier> frontiers = FindFrontiers(map, robot, {}, &stats);
  // ceil(6.0 / 2.5) = 3 pieces of 2 m.
  ASSERT_EQ(frontiers.size(), 3u);
  EXPECT_EQ(stats.clusters, 1);
  EXPECT_EQ(stats.segments, 3);
  std::vector<double> centroid_y;
  for (const Frontier& f : frontiers) {
    EXPECT_EQ(f.size_cells(), 40);
    int min_row = 1000, max_row = -1;
    for (const CellIndex& cell : f.cells) {
      EXPECT_EQ(cell.col, 49);
      min_row = std::min(min_row, cell.row);
      max_row = std::max(max_row, cell.row);
    }
    EXPECT_EQ(max_row - min_row + 1, 40);  // contiguous
    centroid_y.push_back(f.centroid_m.y_m);
  }
  std::sort(centroid_y.begin(), centroid_y.end());
  EXPECT_NEAR(centroid_y[0], (12 + 20) * kRes, 1e-9);
  EXPECT_NEAR(centroid_y[1], (52 + 20) * kRes, 1e-9);
  EXPECT_NEAR(centroid_y[2], (92 + 20) * kRes, 1e-9);
  ExpectTargetsReachable(map, robot, frontiers);

  // Exactly the maximum length stays whole; one cell more makes two.
  FrontierOptions options;
  options.max_segment_length_m = 6.0;
  EXPECT_EQ(FindFrontiers(map, robot, options).size(), 1u);
  options.max_segment_length_m = 5.95;
  EXPECT_EQ(FindFrontiers(map, robot, options).size(), 2u);
}

TEST(FindFrontiers, AnLShapedFrontierIsCutAlongItselfAtTheCorner) {
  // Free cols 12..51 x rows 12..51 (2 m square), walls west and south, open
  // east and north: an L of 40 + 40 - 1 cells, 3.95 m along it -> 2 pieces.
  OccupancyGrid map(70, 70, kRes, {0.0, 0.0}, kU);
  Fill(&map, 10, 10, 51, 51, kO);
  Fill(&map, 12, 12, 51, 51, kF);
  const Point2d robot{1.0, 1.0};
  const std::vector<Frontier> frontiers = FindFrontiers(map, robot, {});
  ASSERT_EQ(frontiers.size(), 2u);
  std::vector<int> sizes;
  for (const Frontier& f : frontiers) {
    sizes.push_back(f.size_cells());
    // Each piece is one arm: all cells but the corner share a row or a column.
    int on_top_row = 0, on_right_col = 0;
    for (const CellIndex& cell : f.cells) {
      on_top_row += cell.row == 51;
      on_right_col += cell.col == 51;
    }
    EXPECT_GE(std::max(on_top_row, on_right_col), f.size_cells() - 1);
    EXPECT_LE(std::min(on_top_row, on_right_col), 1);
  }
  std::sort(sizes.begin(), sizes.end());
  EXPECT_EQ(sizes, (std::vector<int>{39, 40}));
  ExpectTargetsReachable(map, robot, frontiers);
}

TEST(FindFrontiers, ClustersBelowTheMinimumSizeAreDropped) {
  // min_size_m 0.5 at 0.05 m: 10 cells. A 9-cell doorway is dropped, 10 kept.
  OccupancyGrid map = Room();
  EastDoor(&map, 25, 33);
  FrontierExtractionStats stats;
  EXPECT_TRUE(FindFrontiers(map, kRoomCentre, {}, &stats).empty());
  EXPECT_EQ(stats.clusters, 1);
  EXPECT_EQ(stats.clusters_too_small, 1);
  EXPECT_EQ(stats.segments, 0);

  EastDoor(&map, 25, 34);
  const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, {}, &stats);
  ASSERT_EQ(frontiers.size(), 1u);
  EXPECT_EQ(frontiers[0].size_cells(), 10);
  EXPECT_EQ(stats.clusters_too_small, 0);

  // A speck of unknown inside the room (one cell: 8 frontier cells around it) is noise.
  OccupancyGrid speck = Room();
  speck.at({30, 30}) = kU;
  EXPECT_TRUE(FindFrontiers(speck, kRoomCentre, {}, &stats).empty());
  EXPECT_EQ(stats.frontier_cells, 8);
  EXPECT_EQ(stats.clusters_too_small, 1);
}

TEST(FindFrontiers, UnknownCellsInsideWallsMakeNoFrontier) {
  // A closed room whose 3-cell walls have an unknown core: the unknown
  // touches only occupied cells, which are never frontier cells.
  OccupancyGrid map(60, 60, kRes, {0.0, 0.0}, kU);
  Fill(&map, 9, 9, 50, 50, kO);
  Fill(&map, 10, 10, 49, 49, kU);
  Fill(&map, 11, 11, 48, 48, kO);
  Fill(&map, 12, 12, 47, 47, kF);
  FrontierExtractionStats stats;
  EXPECT_TRUE(FindFrontiers(map, kRoomCentre, {}, &stats).empty());
  EXPECT_EQ(stats.frontier_cells, 0);
}

TEST(FindFrontiers, UncertainCellsAreNotFreeUnlessTheThresholdSaysSo) {
  // The doorway reads 40 (SLAM: neither free nor occupied): no frontier at 0,
  // one with free_threshold 40.
  OccupancyGrid map = Room();
  Fill(&map, 48, 25, 49, 35, 40);
  FrontierExtractionStats stats;
  EXPECT_TRUE(FindFrontiers(map, kRoomCentre, {}, &stats).empty());
  EXPECT_EQ(stats.frontier_cells, 0);
  FrontierOptions options;
  options.free_threshold = 40;
  const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, options);
  ASSERT_EQ(frontiers.size(), 1u);
  EXPECT_EQ(frontiers[0].size_cells(), 11);
}

TEST(FindFrontiers, TargetOfANarrowDoorwayLiesInTraversableSpaceInside) {
  // A 0.3 m doorway (6 cells): too narrow for the 0.2 m robot radius (plus
  // the 0.05 m clearance margin), so the target is the nearest traversable
  // free cell inside the room (no cell is asked for more room here).
  OccupancyGrid map = Room();
  EastDoor(&map, 27, 32);
  FrontierOptions options;
  options.min_size_m = 0.3;
  options.target_clearance_m = 0.0;
  const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, options);
  ASSERT_EQ(frontiers.size(), 1u);
  const Frontier& f = frontiers[0];
  EXPECT_LT(f.target_m.x_m, 48 * kRes);  // inside the room, west of the wall
  EXPECT_LE(Distance(f.target_m, f.centroid_m), options.target_radius_m);
  // Centroid (49.5, 30.0) cells. Traversable = more than 5 cells from every
  // obstacle centre: (43, 29) is 5 + 3 cells from the jamb (48, 26), 5.83 > 5,
  // (44, 29) exactly 5; of the two nearest, (43, 29) and (43, 30), the first
  // in row order wins.
  EXPECT_NEAR(f.target_m.x_m, 43.5 * kRes, 1e-9);
  EXPECT_NEAR(f.target_m.y_m, 29.5 * kRes, 1e-9);
  ExpectTargetsReachable(map, kRoomCentre, frontiers);

  // With no traversable cell within the radius the segment is dropped.
  options.target_radius_m = 0.1;
  FrontierExtractionStats stats;
  EXPECT_TRUE(FindFrontiers(map, kRoomCentre, options, &stats).empty());
  EXPECT_EQ(stats.segments, 1);
  EXPECT_EQ(stats.segments_unreachable, 1);
}

// A frontier in a nook: the room's east wall is unseen (unknown) along a 0.6 m gap between two
// cabinets. Its nearest traversable cells are pressed between the cabinets, where a scan return
// the map does not hold shuts the robot out; the target steps back into the room, where it has
// room to stand and still sees the gap.
TEST(FindFrontiers, TargetOfANookStepsBackToWhereTheRobotHasRoom) {
  OccupancyGrid map = Room();
  Fill(&map, 48, 24, 49, 35, kU);  // the unseen stretch of wall
  Fill(&map, 38, 12, 47, 23, kO);  // cabinets either side of it, 0.5 m deep
  Fill(&map, 38, 36, 47, 47, kO);
  FrontierOptions options;
  options.min_size_m = 0.3;
  options.target_clearance_m = 0.0;
  const std::vector<Frontier> pressed = FindFrontiers(map, kRoomCentre, options);
  ASSERT_EQ(pressed.size(), 1u);
  options.target_clearance_m = 0.15;
  const std::vector<Frontier> roomy = FindFrontiers(map, kRoomCentre, options);
  ASSERT_EQ(roomy.size(), 1u);
  EXPECT_EQ(roomy[0].size_cells(), pressed[0].size_cells());  // the same frontier

  // Room = clearance from the cell's centre to the nearest edge of a cell that is not known free.
  auto room_m = [&](Point2d p) {
    const CellIndex cell = map.WorldToCell(p);
    double nearest_m = std::numeric_limits<double>::infinity();
    for (int row = 0; row < map.height_cells(); ++row) {
      for (int col = 0; col < map.width_cells(); ++col) {
        if (map.at({col, row}) == kF) continue;
        nearest_m = std::min(nearest_m, std::hypot(col - cell.col, row - cell.row) * kRes);
      }
    }
    return nearest_m - kRes / 2;
  };
  const double inscribed_m = CostmapOptions{}.robot_radius_m + CostmapOptions{}.clearance_margin_m;
  EXPECT_LT(room_m(pressed[0].target_m), inscribed_m + 0.15);
  EXPECT_GE(room_m(roomy[0].target_m), inscribed_m + 0.15);
  // Stepped back, west of the cabinets' faces, and still within the radius of the centroid.
  EXPECT_LT(roomy[0].target_m.x_m, 38 * kRes);
  EXPECT_GT(Distance(roomy[0].target_m, roomy[0].centroid_m),
            Distance(pressed[0].target_m, pressed[0].centroid_m));
  EXPECT_LE(Distance(roomy[0].target_m, roomy[0].centroid_m), options.target_radius_m);
  ExpectTargetsReachable(map, kRoomCentre, roomy);

  // Buffers kept between extractions follow the option as it changes.
  FrontierScratch scratch;
  for (const double target_clearance_m : {0.15, 0.0, 0.15}) {
    options.target_clearance_m = target_clearance_m;
    const std::vector<Frontier> again = FindFrontiers(map, kRoomCentre, options, nullptr, &scratch);
    ASSERT_EQ(again.size(), 1u);
    const Point2d expected = target_clearance_m > 0.0 ? roomy[0].target_m : pressed[0].target_m;
    EXPECT_EQ(Distance(again[0].target_m, expected), 0.0) << target_clearance_m;
  }
}

TEST(FindFrontiers, FrontiersTheRobotCannotReachAreDropped) {
  // Room A (the robot's) has an east doorway; room B beside it is walled off
  // and holds an unknown pocket: its frontier cannot be reached, even through
  // the unknown (unknown is passable, as for the navigator).
  OccupancyGrid map(120, 60, kRes, {0.0, 0.0}, kU);
  Fill(&map, 10, 10, 49, 49, kO);
  Fill(&map, 12, 12, 47, 47, kF);
  EastDoor(&map, 25, 35);
  Fill(&map, 60, 10, 109, 49, kO);
  Fill(&map, 62, 12, 107, 47, kF);
  Fill(&map, 80, 25, 90, 35, kU);  // pocket: 0.55 m square, 13 * 13 - 11 * 11 = 48 cells around it
  FrontierExtractionStats stats;
  const std::vector<Frontier> frontiers = FindFrontiers(map, kRoomCentre, {}, &stats);
  ASSERT_EQ(frontiers.size(), 1u);
  EXPECT_LT(frontiers[0].centroid_m.x_m, 2.5);  // room A's doorway
  EXPECT_EQ(stats.clusters, 2);
  EXPECT_EQ(stats.segments, 2);
  EXPECT_EQ(stats.segments_unreachable, 1);
  // Seen from room B the pocket is the reachable one (the doorway is not:
  // room A is closed to room B).
  const Point2d in_b{3.5, 0.9};
  const std::vector<Frontier> from_b = FindFrontiers(map, in_b, {});
  ASSERT_EQ(from_b.size(), 1u);
  EXPECT_GT(from_b[0].centroid_m.x_m, 3.9);
  EXPECT_EQ(from_b[0].size_cells(), 48);
  ExpectTargetsReachable(map, in_b, from_b);
}

// Issue 15's dead-end pinch: the robot stands in a traversable pocket whose only gap the
// inscribed zone closes (office, ags, seeds 1 and 5 stopped `done` there at 24 % and 48 %). The
// frontiers outside must stay reachable, as the planner's start escape makes them.
TEST(FindFrontiers, RobotShutInAPocketStillReachesTheFrontiersOutside) {
  OccupancyGrid map(100, 60, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 60; ++row) {
    for (int col = 90; col < 100; ++col) map.at({col, row}) = OccupancyGrid::kUnknown;
  }
  for (int col = 40; col <= 60; ++col) {
    map.at({col, 20}) = OccupancyGrid::kOccupied;
    map.at({col, 36}) = OccupancyGrid::kOccupied;
  }
  for (int row = 20; row <= 36; ++row) {
    map.at({60, row}) = OccupancyGrid::kOccupied;
    // A 0.45 m gap: the robot's body fits, its clearance margin does not.
    if (row < 24 || row > 32) map.at({40, row}) = OccupancyGrid::kOccupied;
  }
  const Point2d in_pocket = map.CellCenter({50, 28});
  FrontierExtractionStats stats;
  const std::vector<Frontier> frontiers = FindFrontiers(map, in_pocket, {}, &stats);
  EXPECT_TRUE(stats.used_planner_search);
  ASSERT_FALSE(frontiers.empty());
  for (const Frontier& f : frontiers) EXPECT_GT(f.target_m.x_m, 60 * kRes);  // out of the box
  ExpectTargetsReachable(map, in_pocket, frontiers);
  // Outside the pocket nothing changes: the same frontiers, found by components.
  const std::vector<Frontier> from_outside =
      FindFrontiers(map, map.CellCenter({15, 28}), {}, &stats);
  EXPECT_FALSE(stats.used_planner_search);
  EXPECT_EQ(from_outside.size(), frontiers.size());
}

TEST(FindFrontiers, RobotAgainstAWallUsesThePlannerAndFindsTheSameTargets) {
  OccupancyGrid map = Room();
  EastDoor(&map, 25, 35);
  NorthDoor(&map, 15, 26);
  const Point2d against_wall{12.5 * kRes + 0.05, 1.5};  // 0.1 m from the west wall: inscribed
  FrontierExtractionStats stats;
  const std::vector<Frontier> a = FindFrontiers(map, against_wall, {}, &stats);
  EXPECT_TRUE(stats.used_planner_search);
  const std::vector<Frontier> b = FindFrontiers(map, kRoomCentre, {}, &stats);
  EXPECT_FALSE(stats.used_planner_search);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].target_m.x_m, b[i].target_m.x_m);
    EXPECT_EQ(a[i].target_m.y_m, b[i].target_m.y_m);
  }
  // Off the map nothing is reachable.
  EXPECT_TRUE(FindFrontiers(map, {-1.0, 1.0}, {}, &stats).empty());
  EXPECT_EQ(stats.segments_unreachable, 2);
}

TEST(FindFrontiers, NoUnknownOrEmptyMapGivesNothing) {
  EXPECT_TRUE(FindFrontiers(OccupancyGrid(), {0.0, 0.0}, {}).empty());
  OccupancyGrid known(40, 40, kRes, {0.0, 0.0}, kF);
  EXPECT_TRUE(FindFrontiers(known, {1.0, 1.0}, {}).empty());  // off-map is not unknown
}

// ---------------------------------------------------------------------------
// Ids

Frontier At(int id, double x_m, double y_m) {
  Frontier f;
  f.id = id;
  f.centroid_m = {x_m, y_m};
  return f;
}

TEST(AssignFrontierIds, ClosestPairsFirstOneToOneWithinTheThreshold) {
  const std::vector<Frontier> previous = {At(5, 0.0, 0.0), At(7, 1.0, 0.0)};
  // 0.9 is nearer 7 (0.1) than 5 (0.9); 0.3 and 0.1 both near 5: the closer one wins,
  // the other (0.3 from 5, 0.7 from 7, 7 taken) is new; (5, 5) is far from all.
  std::vector<Frontier> current = {At(-1, 0.9, 0.0), At(-1, 0.3, 0.0), At(-1, 0.1, 0.0),
                                   At(-1, 5.0, 5.0)};
  int next_id = 8;
  AssignFrontierIds(previous, 1.0, &current, &next_id);
  ASSERT_EQ(current.size(), 4u);
  // Sorted by id.
  EXPECT_EQ(current[0].id, 5);
  EXPECT_DOUBLE_EQ(current[0].centroid_m.x_m, 0.1);
  EXPECT_EQ(current[1].id, 7);
  EXPECT_DOUBLE_EQ(current[1].centroid_m.x_m, 0.9);
  EXPECT_EQ(current[2].id, 8);
  EXPECT_DOUBLE_EQ(current[2].centroid_m.x_m, 0.3);
  EXPECT_EQ(current[3].id, 9);
  EXPECT_EQ(next_id, 10);

  // Beyond the threshold nothing matches.
  std::vector<Frontier> moved = {At(-1, 0.0, 0.6)};
  AssignFrontierIds(previous, 0.5, &moved, &next_id);
  EXPECT_EQ(moved[0].id, 10);
}

TEST(FrontierExtractor, IdsSurviveASmallMapChangeAndAreNeverReused) {
  FrontierExtractor extractor;
  OccupancyGrid map = Room();
  EastDoor(&map, 25, 35);
  NorthDoor(&map, 15, 26);
  const std::vector<Frontier> first = extractor.Extract(map, kRoomCentre);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].id, 0);
  EXPECT_EQ(first[1].id, 1);
  const bool east_first = first[0].centroid_m.x_m > first[1].centroid_m.x_m;
  const int east_id = east_first ? first[0].id : first[1].id;

  // Reveal three columns beyond the east door (the frontier moves out 0.15 m),
  // close the north door's outside (its frontier vanishes), open a west door.
  Fill(&map, 50, 25, 52, 35, kF);
  Fill(&map, 13, 50, 28, 53, kO);
  WestDoor(&map, 20, 31);
  const std::vector<Frontier> second = extractor.Extract(map, kRoomCentre);
  ASSERT_EQ(second.size(), 2u);
  EXPECT_EQ(second[0].id, east_id);
  EXPECT_GT(second[0].centroid_m.x_m, 2.5);  // the east one, moved out
  EXPECT_EQ(second[1].id, 2);                // the west door: a fresh id
  EXPECT_LT(second[1].centroid_m.x_m, 0.6);
  EXPECT_EQ(extractor.next_id(), 3);

  // The north door's frontier comes back: a new id, not its old one.
  Fill(&map, 13, 50, 28, 53, kU);
  const std::vector<Frontier> third = extractor.Extract(map, kRoomCentre);
  ASSERT_EQ(third.size(), 3u);
  EXPECT_EQ(third[0].id, east_id);
  EXPECT_EQ(third[1].id, 2);
  EXPECT_EQ(third[2].id, 3);
  EXPECT_GT(third[2].centroid_m.y_m, 2.4);  // north
  ExpectTargetsReachable(map, kRoomCentre, third);
}

TEST(FrontierOptions, ValidateNamesTheField) {
  FrontierOptions options;
  options.max_segment_length_m = 0.0;
  EXPECT_THROW(
      {
        try {
          options.Validate();
        } catch (const std::invalid_argument& e) {
          EXPECT_THAT(e.what(), ::testing::HasSubstr("max_segment_length_m"));
          throw;
        }
      },
      std::invalid_argument);
  options = FrontierOptions{};
  options.free_threshold = 65;  // = the costmap's occupied threshold
  EXPECT_THROW(FrontierExtractor{options}, std::invalid_argument);
  options = FrontierOptions{};
  options.costmap.robot_radius_m = -1.0;
  EXPECT_THROW(FrontierExtractor{options}, std::invalid_argument);
}

// ---------------------------------------------------------------------------
// Campus scale: reachability agrees with the planner; timing (printed, not asserted).

const WorldInfo& Campus() {
  static const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus");
  return world;
}

// The campus as if explored `steps_cells` (4-connected steps over free cells)
// around the start: those free cells and the cells touching them are known.
OccupancyGrid PartlyExplored(int steps_cells) {
  const OccupancyGrid& truth = Campus().map.grid;
  OccupancyGrid map(truth.width_cells(), truth.height_cells(), truth.resolution_m(),
                    truth.origin_m(), kU);
  std::vector<int> depth(truth.cells().size(), -1);
  std::deque<CellIndex> queue;
  const CellIndex start = truth.WorldToCell({Campus().start.x_m, Campus().start.y_m});
  depth[truth.LinearIndex(start)] = 0;
  queue.push_back(start);
  const int dc[4] = {1, -1, 0, 0};
  const int dr[4] = {0, 0, 1, -1};
  while (!queue.empty()) {
    const CellIndex u = queue.front();
    queue.pop_front();
    for (int r = -1; r <= 1; ++r) {
      for (int c = -1; c <= 1; ++c) {
        const CellIndex v{u.col + c, u.row + r};
        if (truth.Contains(v)) map.at(v) = truth.at(v);
      }
    }
    if (depth[truth.LinearIndex(u)] >= steps_cells) continue;
    for (int k = 0; k < 4; ++k) {
      const CellIndex v{u.col + dc[k], u.row + dr[k]};
      if (!truth.Contains(v) || truth.at(v) != kF || depth[truth.LinearIndex(v)] >= 0) continue;
      depth[truth.LinearIndex(v)] = depth[truth.LinearIndex(u)] + 1;
      queue.push_back(v);
    }
  }
  return map;
}

TEST(ReachableCells, AgreesWithAGlobalPlannerSearchOnCampus) {
  const OccupancyGrid map = PartlyExplored(600);
  const Point2d start_m{Campus().start.x_m, Campus().start.y_m};
  for (const bool unknown_passable : {true, false}) {
    CostmapOptions costmap_options;
    costmap_options.unknown_passable = unknown_passable;
    const Costmap costmap(map, costmap_options);
    const CellIndex robot = costmap.WorldToCell(start_m);
    // The start, a cell against a wall (planner fallback), and the first
    // traversable cell in row order (in the unknown when that is passable).
    std::vector<CellIndex> starts = {robot};
    for (int col = robot.col; col < costmap.width_cells(); ++col) {
      if (!costmap.Traversable({col, robot.row})) {
        starts.push_back({col, robot.row});
        break;
      }
    }
    for (std::size_t i = 0; i < costmap.costs().size(); ++i) {
      if (costmap.costs()[i] < Costmap::kInscribed) {
        starts.push_back({static_cast<int>(i % costmap.width_cells()),
                          static_cast<int>(i / costmap.width_cells())});
        break;
      }
    }
    for (const CellIndex& start : starts) {
      SCOPED_TRACE(::testing::Message() << "unknown_passable " << unknown_passable << " start "
                                        << start.col << "," << start.row);
      const ReachableCells reachable(costmap, start, GlobalPlannerOptions{});
      const ShortestPathTree tree = GlobalPlanner().Search(costmap, start);
      int disagreements = 0, reached = 0;
      for (int row = 0; row < costmap.height_cells(); ++row) {
        for (int col = 0; col < costmap.width_cells(); ++col) {
          const CellIndex cell{col, row};
          const bool expected = costmap.Traversable(cell) && tree.Reachable(cell);
          disagreements += reachable.Reachable(cell) != expected;
          reached += expected;
        }
      }
      EXPECT_EQ(disagreements, 0);
      EXPECT_GT(reached, start == robot ? 100000 : 0);
      if (!costmap.Traversable(start)) {
        EXPECT_TRUE(reachable.used_planner_search());
      }
      if (start == robot) {
        EXPECT_FALSE(reachable.used_planner_search());
      }
    }
  }
}

// Clusters whose cells did not change keep last extraction's segments; what comes out is
// what a fresh extraction gives, map after map (grown, unchanged, changed in one place).
TEST(FindFrontiers, ReusedScratchSplitsOnlyChangedClustersAndGivesTheSameFrontiers) {
  const Point2d robot{Campus().start.x_m, Campus().start.y_m};
  OccupancyGrid changed = PartlyExplored(600);
  // A 1 m square of the unknown next to known free space becomes free: one cluster changes.
  bool done = false;
  for (int row = 20; row + 20 < changed.height_cells() && !done; ++row) {
    for (int col = 20; col + 20 < changed.width_cells() && !done; ++col) {
      if (changed.at({col, row}) == kF && changed.at({col + 1, row}) == kU) {
        Fill(&changed, col + 1, row - 10, col + 20, row + 10, kF);
        done = true;
      }
    }
  }
  ASSERT_TRUE(done);
  FrontierScratch scratch;
  std::vector<int> split;
  int kept_clusters = 0;
  for (const OccupancyGrid& map :
       {PartlyExplored(200), PartlyExplored(600), PartlyExplored(600), changed}) {
    FrontierExtractionStats reused_stats, fresh_stats;
    const std::vector<Frontier> reused = FindFrontiers(map, robot, {}, &reused_stats, &scratch);
    const std::vector<Frontier> fresh = FindFrontiers(map, robot, {}, &fresh_stats);
    ASSERT_EQ(reused.size(), fresh.size());
    for (std::size_t i = 0; i < fresh.size(); ++i) {
      EXPECT_EQ(reused[i].cells, fresh[i].cells) << "frontier " << i;
      EXPECT_EQ(reused[i].target_m.x_m, fresh[i].target_m.x_m) << "frontier " << i;
      EXPECT_EQ(reused[i].target_m.y_m, fresh[i].target_m.y_m) << "frontier " << i;
    }
    EXPECT_EQ(fresh_stats.clusters_split, fresh_stats.clusters - fresh_stats.clusters_too_small);
    split.push_back(reused_stats.clusters_split);
    kept_clusters = fresh_stats.clusters - fresh_stats.clusters_too_small;
  }
  EXPECT_EQ(split[2], 0);                  // the same map again: nothing split
  EXPECT_GT(split[3], 0);                  // the change split again...
  EXPECT_LT(split[3], kept_clusters / 2);  // ...where it is, not everywhere
}

// The reachable cell nearest the centroid that `accept` takes among the segment's cells (the
// first of equals) and the known-free reachable cells within the radius whose Bresenham line to
// the segment's cell nearest the centroid is all known free (strictly nearer than the segment's
// best; of equals, the first in raster order).
template <typename Accept>
std::optional<CellIndex> BruteForceTarget(const OccupancyGrid& map, const ReachableCells& reachable,
                                          const Frontier& f, double radius_m,
                                          const Accept& accept) {
  auto d2 = [&](CellIndex cell) {
    const Point2d p = map.CellCenter(cell);
    return std::pow(p.x_m - f.centroid_m.x_m, 2) + std::pow(p.y_m - f.centroid_m.y_m, 2);
  };
  auto known_free = [&](CellIndex cell) { return map.at(cell) == kF; };
  auto clear_line = [&](CellIndex a, CellIndex b) {
    const int dc = std::abs(b.col - a.col), dr = -std::abs(b.row - a.row);
    const int sc = a.col < b.col ? 1 : -1, sr = a.row < b.row ? 1 : -1;
    int error = dc + dr;
    for (CellIndex c = a;;) {
      if (!known_free(c)) return false;
      if (c.col == b.col && c.row == b.row) return true;
      const int e2 = 2 * error;
      if (e2 >= dr) error += dr, c.col += sc;
      if (e2 <= dc) error += dc, c.row += sr;
    }
  };
  CellIndex anchor = f.cells.front();
  std::optional<CellIndex> best;
  for (const CellIndex& cell : f.cells) {
    if (d2(cell) < d2(anchor)) anchor = cell;
    if (reachable.Reachable(cell) && accept(cell) && (!best || d2(cell) < d2(*best))) best = cell;
  }
  std::optional<CellIndex> window_best;
  for (int row = 0; row < map.height_cells(); ++row) {
    for (int col = 0; col < map.width_cells(); ++col) {
      const CellIndex cell{col, row};
      if (std::sqrt(d2(cell)) > radius_m || !known_free(cell) || !reachable.Reachable(cell) ||
          !accept(cell) || !clear_line(cell, anchor)) {
        continue;
      }
      if (!window_best || d2(cell) < d2(*window_best)) window_best = cell;
    }
  }
  if (window_best && (!best || d2(*window_best) < d2(*best))) return window_best;
  return best;
}

// Step 4 by brute force, as the header states it: first only the cells with room_m of clearance
// (centre to edge) to every cell that is not known free or off the map, then any (room_m 0: any
// at once).
std::optional<CellIndex> BruteForceTarget(const OccupancyGrid& map, const ReachableCells& reachable,
                                          const Frontier& f, double radius_m, double room_m) {
  auto has_room = [&](CellIndex cell) {
    const int reach = static_cast<int>(std::ceil(room_m / kRes)) + 1;
    for (int row = cell.row - reach; row <= cell.row + reach; ++row) {
      for (int col = cell.col - reach; col <= cell.col + reach; ++col) {
        if (map.Contains({col, row}) && map.at({col, row}) == kF) continue;
        if (std::hypot(col - cell.col, row - cell.row) * kRes - kRes / 2 < room_m) return false;
      }
    }
    return true;
  };
  if (room_m > 0.0) {
    if (auto roomy = BruteForceTarget(map, reachable, f, radius_m, has_room)) return roomy;
  }
  return BruteForceTarget(map, reachable, f, radius_m, [](CellIndex) { return true; });
}

TEST(FindFrontiers, TargetsAreTheNearestValidCellsFoundByBruteForce) {
  const Point2d robot{Campus().start.x_m, Campus().start.y_m};
  int checked = 0, off_the_segment = 0, with_room = 0;
  double farthest_target_m = 0.0;
  // A wide robot keeps targets off the walls, far from their centroids; with no room asked
  // for, the nearest traversable cell is the target.
  for (const auto& [robot_radius_m, target_clearance_m] :
       std::vector<std::pair<double, double>>{{CostmapOptions{}.robot_radius_m, 0.15},
                                              {CostmapOptions{}.robot_radius_m, 0.0},
                                              {0.45, 0.15}}) {
    for (const int steps : {150, 400, 900}) {
      const OccupancyGrid map = PartlyExplored(steps);
      FrontierOptions options;
      options.costmap.robot_radius_m = robot_radius_m;
      options.target_clearance_m = target_clearance_m;
      const double room_m =
          target_clearance_m > 0.0
              ? robot_radius_m + options.costmap.clearance_margin_m + target_clearance_m
              : 0.0;
      const std::vector<Frontier> frontiers = FindFrontiers(map, robot, options);
      const Costmap costmap(map, options.costmap);
      const ReachableCells reachable(costmap, map.WorldToCell(robot), options.global_planner);
      for (const Frontier& f : frontiers) {
        const std::optional<CellIndex> expected =
            BruteForceTarget(map, reachable, f, options.target_radius_m, room_m);
        ASSERT_TRUE(expected.has_value()) << "frontier " << f.id;
        if (room_m > 0.0) {
          with_room += BruteForceTarget(map, reachable, f, options.target_radius_m, room_m) !=
                       BruteForceTarget(map, reachable, f, options.target_radius_m, 0.0);
        }
        const CellIndex target = map.WorldToCell(f.target_m);
        EXPECT_EQ(target.col, expected->col) << "steps " << steps << " frontier " << f.id;
        EXPECT_EQ(target.row, expected->row) << "steps " << steps << " frontier " << f.id;
        off_the_segment += std::none_of(f.cells.begin(), f.cells.end(), [&](const CellIndex& c) {
          return c.col == target.col && c.row == target.row;
        });
        farthest_target_m = std::max(farthest_target_m, Distance(f.target_m, f.centroid_m));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 40);
  EXPECT_GT(with_room, 0);            // room to stand moved some targets...
  EXPECT_GT(off_the_segment, 0);      // the window search decided some targets...
  EXPECT_GT(farthest_target_m, 0.3);  // ...some of them far from the centroid
}

TEST(FindFrontiers, CampusSizedMapTargetsReachableAndTiming) {
  const Point2d robot{Campus().start.x_m, Campus().start.y_m};
  for (const int steps : {200, 600, 1000}) {
    const OccupancyGrid map = PartlyExplored(steps);
    FrontierExtractionStats stats;
    const std::vector<Frontier> frontiers = FindFrontiers(map, robot, {}, &stats);
    EXPECT_FALSE(frontiers.empty());
    EXPECT_FALSE(stats.used_planner_search);
    EXPECT_EQ(static_cast<int>(frontiers.size()), stats.segments - stats.segments_unreachable);
    for (const Frontier& f : frontiers) {
      EXPECT_LE(f.size_cells() * kRes, 2 * 2.5 * M_SQRT2);  // bounded (a 2-cell-thick band at most)
    }
    ExpectTargetsReachable(map, robot, frontiers);

    // Timing, for the record: extraction (as the node runs it, buffers reused)
    // vs a Costmap alone and one one-to-all planner search.
    constexpr int kRepeats = 5;
    FrontierExtractor extractor;
    extractor.Extract(map, robot);  // warm-up: the buffers
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kRepeats; ++i) extractor.Extract(map, robot);
    const auto t1 = std::chrono::steady_clock::now();
    const Costmap costmap(map, CostmapOptions{});
    const auto t2 = std::chrono::steady_clock::now();
    ShortestPathTree tree;
    for (int i = 0; i < kRepeats; ++i) {
      GlobalPlanner().Search(costmap, costmap.WorldToCell(robot), {}, &tree);
    }
    const auto t3 = std::chrono::steady_clock::now();
    const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
    const OccupancyGrid::CellCounts counts = map.CountCells();
    std::printf(
        "campus %dx%d, explored %d steps (%zu free, %zu unknown cells): %zu frontiers "
        "(%d frontier cells, %d clusters, %d too small, %d unreachable); Extract "
        "%.1f ms; costmap %.1f ms; one-to-all Search %.1f ms\n",
        map.width_cells(), map.height_cells(), steps, counts.free, counts.unknown, frontiers.size(),
        stats.frontier_cells, stats.clusters, stats.clusters_too_small, stats.segments_unreachable,
        ms(t1 - t0) / kRepeats, ms(t2 - t1), ms(t3 - t2) / kRepeats);
  }
}

}  // namespace
}  // namespace aslam
