#include "navigation/local_obstacles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace aslam {
namespace {

constexpr double kRes = 0.05;
constexpr double kHalfCell = 0.5 * kRes;
constexpr double kTol = 1e-5;  // float storage of the distance field

// Distance from `p` to the axis-aligned square [x0, x1] x [y0, y1].
double DistanceToBox(const Point2d& p, double x0, double y0, double x1, double y1) {
  const double dx = std::max({x0 - p.x_m, 0.0, p.x_m - x1});
  const double dy = std::max({y0 - p.y_m, 0.0, p.y_m - y1});
  return std::hypot(dx, dy);
}

bool InWindow(const LocalObstacles& obstacles, const Point2d& p) {
  const double size_m = obstacles.size_cells() * obstacles.resolution_m();
  return p.x_m >= obstacles.origin_m().x_m && p.y_m >= obstacles.origin_m().y_m &&
         p.x_m < obstacles.origin_m().x_m + size_m && p.y_m < obstacles.origin_m().y_m + size_m;
}

// Random map cells and scan points: the layer's clearance against the nearest
// obstacle found by looping over every obstacle cell and point in the window.
TEST(LocalObstaclesTest, ClearanceMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_optimistic_m = -1.0, worst_cell_error_m = 0.0;
  for (int trial = 0; trial < 6; ++trial) {
    OccupancyGrid map(120, 100, kRes, {-2.0 + 0.3 * trial, -1.5}, OccupancyGrid::kFree);
    for (int8_t& cell : map.mutable_cells()) {
      const double u = unit(rng);
      cell = u < 0.004  ? OccupancyGrid::kOccupied
             : u < 0.3  ? OccupancyGrid::kUnknown
             : u < 0.35 ? 50  // below the threshold: not an obstacle
                        : OccupancyGrid::kFree;
    }
    const Pose2d robot{map.origin_m().x_m + 3.0 + unit(rng), map.origin_m().y_m + 2.5 + unit(rng),
                       0.3};
    std::vector<Point2d> scan;
    for (int i = 0; i < 40; ++i) {
      scan.push_back({robot.x_m - 3.0 + 6.0 * unit(rng), robot.y_m - 3.0 + 6.0 * unit(rng)});
    }
    LocalObstaclesOptions options;
    options.window_m = 4.0;
    const LocalObstacles obstacles(map, scan, robot, options);
    ASSERT_EQ(obstacles.size_cells(), 80);

    for (int q = 0; q < 400; ++q) {
      // Keep half a cell off the window's edge, where the field ends.
      const Point2d p{obstacles.origin_m().x_m + kHalfCell + (4.0 - kRes) * unit(rng),
                      obstacles.origin_m().y_m + kHalfCell + (4.0 - kRes) * unit(rng)};
      double to_point_m = std::numeric_limits<double>::infinity();  // obstacle points themselves
      double to_cell_m = std::numeric_limits<double>::infinity();   // their cells as squares
      for (int row = 0; row < map.height_cells(); ++row) {
        for (int col = 0; col < map.width_cells(); ++col) {
          if (map.at({col, row}) < options.occupied_threshold) continue;
          const Point2d centre = map.CellCenter({col, row});
          if (!InWindow(obstacles, centre)) continue;
          const double d = DistanceToBox(p, centre.x_m - kHalfCell, centre.y_m - kHalfCell,
                                         centre.x_m + kHalfCell, centre.y_m + kHalfCell);
          to_point_m = std::min(to_point_m, d);
          to_cell_m = std::min(to_cell_m, d);
        }
      }
      for (const Point2d& s : scan) {
        if (!InWindow(obstacles, s)) continue;
        to_point_m = std::min(to_point_m, std::hypot(p.x_m - s.x_m, p.y_m - s.y_m));
        const double x0 =
            obstacles.origin_m().x_m + std::floor((s.x_m - obstacles.origin_m().x_m) / kRes) * kRes;
        const double y0 =
            obstacles.origin_m().y_m + std::floor((s.y_m - obstacles.origin_m().y_m) / kRes) * kRes;
        to_cell_m = std::min(to_cell_m, DistanceToBox(p, x0, y0, x0 + kRes, y0 + kRes));
      }
      const double clearance_m = obstacles.ClearanceM(p);
      // Never more than half a cell optimistic about any obstacle point...
      EXPECT_LE(clearance_m, to_point_m + kHalfCell + kTol) << "query " << p.x_m << "," << p.y_m;
      // ...and within half a cell of the distance to the nearest obstacle cell.
      EXPECT_NEAR(clearance_m, to_cell_m, kHalfCell + kTol) << "query " << p.x_m << "," << p.y_m;
      worst_optimistic_m = std::max(worst_optimistic_m, clearance_m - to_point_m);
      worst_cell_error_m = std::max(worst_cell_error_m, std::abs(clearance_m - to_cell_m));
    }
  }
  RecordProperty("worst_optimistic_mm", static_cast<int>(worst_optimistic_m * 1000));
  RecordProperty("worst_cell_error_mm", static_cast<int>(worst_cell_error_m * 1000));
}

TEST(LocalObstaclesTest, ScanPointsAreStampedIntoAnEmptyMap) {
  const Pose2d robot{10.0, -4.0, 0.0};
  const Point2d point{11.0, -4.0};
  const LocalObstacles obstacles(OccupancyGrid(), {point}, robot, LocalObstaclesOptions());
  EXPECT_LE(obstacles.ClearanceM(point), kHalfCell);
  EXPECT_NEAR(obstacles.ClearanceM({robot.x_m, robot.y_m}), 1.0, kRes);
  EXPECT_NEAR(obstacles.ClearanceM({11.0, -3.0}), 1.0, kRes);
  // Without the point nothing is near.
  const LocalObstacles none(OccupancyGrid(), {}, robot, LocalObstaclesOptions());
  EXPECT_GT(none.ClearanceM({robot.x_m, robot.y_m}), 4.0);
  EXPECT_GT(none.ClearanceM(point), 4.0);
}

TEST(LocalObstaclesTest, UnknownCellsAreNotObstacles) {
  OccupancyGrid map(200, 200, kRes, {-5.0, -5.0}, OccupancyGrid::kUnknown);
  const Pose2d robot{0.0, 0.0, 0.0};
  const LocalObstacles all_unknown(map, {}, robot, LocalObstaclesOptions());
  EXPECT_GT(all_unknown.ClearanceM({0.0, 0.0}), 4.0);
  EXPECT_GT(all_unknown.ClearanceM({1.0, 1.0}), 4.0);

  // One occupied cell among unknown ones: clearance measures to it alone.
  const CellIndex wall = map.WorldToCell({2.0, 0.0});
  map.at(wall) = OccupancyGrid::kOccupied;
  const LocalObstacles one_wall(map, {}, robot, LocalObstaclesOptions());
  const Point2d centre = map.CellCenter(wall);
  EXPECT_NEAR(one_wall.ClearanceM({centre.x_m - 1.0, centre.y_m}), 1.0 - kHalfCell, kTol);
  EXPECT_LE(one_wall.ClearanceM(centre), kTol);
  // Below the occupied threshold is not an obstacle either.
  map.at(wall) = 64;
  const LocalObstacles below(map, {}, robot, LocalObstaclesOptions());
  EXPECT_GT(below.ClearanceM({centre.x_m - 1.0, centre.y_m}), 4.0);
}

TEST(LocalObstaclesTest, OutsideTheWindowIsBlocked) {
  const Pose2d robot{1.0, 2.0, 0.0};
  LocalObstaclesOptions options;
  options.window_m = 8.0;
  const LocalObstacles obstacles(OccupancyGrid(), {}, robot, options);
  EXPECT_GT(obstacles.ClearanceM({robot.x_m + 3.8, robot.y_m}), 1.0);
  EXPECT_GT(obstacles.ClearanceM({robot.x_m - 3.8, robot.y_m - 3.8}), 1.0);
  EXPECT_EQ(obstacles.ClearanceM({robot.x_m + 4.2, robot.y_m}), 0.0);
  EXPECT_EQ(obstacles.ClearanceM({robot.x_m, robot.y_m - 4.2}), 0.0);
  EXPECT_EQ(obstacles.ClearanceM({robot.x_m + 100.0, robot.y_m + 100.0}), 0.0);
  EXPECT_EQ(obstacles.ClearanceM({std::nan(""), robot.y_m}), 0.0);
  EXPECT_EQ(LocalObstacles().ClearanceM({0.0, 0.0}), 0.0);  // default: all blocked
}

TEST(LocalObstaclesTest, CoarserMapCellsCoverEveryWindowCellTheyOverlap) {
  // A 0.1 m map under the 0.05 m window: the occupied cell [1.0, 1.1) x [0, 0.1).
  OccupancyGrid map(100, 100, 0.1, {-5.0, -5.0}, OccupancyGrid::kFree);
  map.at(map.WorldToCell({1.05, 0.05})) = OccupancyGrid::kOccupied;
  const LocalObstacles obstacles(map, {}, {0.0, 0.0, 0.0}, LocalObstaclesOptions());
  // All four window cells under it are obstacles (their centres read 0)...
  for (const Point2d p : {Point2d{1.025, 0.025}, Point2d{1.075, 0.025}, Point2d{1.025, 0.075},
                          Point2d{1.075, 0.075}}) {
    EXPECT_LE(obstacles.ClearanceM(p), kTol) << p.x_m << ", " << p.y_m;
  }
  // ...and their neighbours outside it are not.
  EXPECT_NEAR(obstacles.ClearanceM({1.125, 0.025}), kHalfCell, kTol);
  EXPECT_NEAR(obstacles.ClearanceM({0.975, 0.075}), kHalfCell, kTol);
  EXPECT_NEAR(obstacles.ClearanceM({1.025, 0.125}), kHalfCell, kTol);
  EXPECT_NEAR(obstacles.ClearanceM({0.5, 0.05}), 0.5, kHalfCell + kTol);
  EXPECT_NEAR(obstacles.ClearanceM({1.6, 0.05}), 0.5, kHalfCell + kTol);
}

TEST(LocalObstaclesTest, BadOptionsThrowNamingTheOption) {
  LocalObstaclesOptions options;
  options.resolution_m = 0.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.window_m = 0.01;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.occupied_threshold = 0;
  try {
    options.Validate();
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("occupied_threshold"), std::string::npos);
  }
  EXPECT_NO_THROW(LocalObstaclesOptions().Validate());
}

}  // namespace
}  // namespace aslam
