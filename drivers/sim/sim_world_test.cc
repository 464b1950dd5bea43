#include "drivers/sim/sim_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace aslam {
namespace {

constexpr double kResolutionM = 0.05;

// A room whose free interior is exactly [x_min, x_max] x [y_min, y_max]
// (walls one cell thick on cell boundaries, origin deliberately off zero).
struct Room {
  OccupancyGrid grid;
  double x_min, x_max, y_min, y_max;
};

Room MakeRoom(int width_cells, int height_cells, double resolution_m = kResolutionM,
              Point2d origin = {-1.3, 2.15}) {
  Room room{OccupancyGrid(width_cells, height_cells, resolution_m, origin, OccupancyGrid::kFree),
            origin.x_m + resolution_m, origin.x_m + (width_cells - 1) * resolution_m,
            origin.y_m + resolution_m, origin.y_m + (height_cells - 1) * resolution_m};
  for (int col = 0; col < width_cells; ++col) {
    room.grid.at({col, 0}) = OccupancyGrid::kOccupied;
    room.grid.at({col, height_cells - 1}) = OccupancyGrid::kOccupied;
  }
  for (int row = 0; row < height_cells; ++row) {
    room.grid.at({0, row}) = OccupancyGrid::kOccupied;
    room.grid.at({width_cells - 1, row}) = OccupancyGrid::kOccupied;
  }
  return room;
}

// Distance from p along angle to the boundary of the box, p inside it.
double DistanceToBox(const Room& room, Point2d p, double angle_rad) {
  const double dx = std::cos(angle_rad), dy = std::sin(angle_rad);
  double t = std::numeric_limits<double>::infinity();
  if (dx > 0) t = std::min(t, (room.x_max - p.x_m) / dx);
  if (dx < 0) t = std::min(t, (room.x_min - p.x_m) / dx);
  if (dy > 0) t = std::min(t, (room.y_max - p.y_m) / dy);
  if (dy < 0) t = std::min(t, (room.y_min - p.y_m) / dy);
  return t;
}

TEST(SimWorldTest, SolidCellsFollowTheMapValues) {
  OccupancyGrid grid(4, 3, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  grid.at({1, 0}) = OccupancyGrid::kUnknown;
  grid.at({2, 0}) = 1;
  grid.at({3, 0}) = 100;
  const SimWorld world(grid);
  EXPECT_FALSE(world.IsSolid({0, 0}));
  EXPECT_TRUE(world.IsSolid({1, 0}));
  EXPECT_TRUE(world.IsSolid({2, 0}));
  EXPECT_TRUE(world.IsSolid({3, 0}));
  EXPECT_FALSE(world.IsSolid({3, 2}));
  EXPECT_TRUE(world.IsSolid({-1, 0}));
  EXPECT_TRUE(world.IsSolid({4, 2}));
  EXPECT_TRUE(world.IsSolid({1000000, -1000000}));
  EXPECT_TRUE(world.IsSolidAt({-0.01, 0.05}));
  EXPECT_FALSE(world.IsSolidAt({0.05, 0.05}));
  EXPECT_NEAR(world.free_area_m2(), 9 * 0.01, 1e-12);
}

TEST(SimWorldTest, RaysInARoomMatchTheAnalyticDistance) {
  const Room room = MakeRoom(120, 90);
  const SimWorld world(room.grid);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(room.x_min + 0.01, room.x_max - 0.01);
  std::uniform_real_distribution<double> uy(room.y_min + 0.01, room.y_max - 0.01);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int i = 0; i < 2000; ++i) {
    const Point2d p{ux(rng), uy(rng)};
    const double a = angle(rng);
    const double expected = DistanceToBox(room, p, a);
    EXPECT_NEAR(world.CastRay(p, a, 100.0), expected, 1e-9) << p.x_m << " " << p.y_m << " " << a;
    EXPECT_NEAR(world.CastRayPlain(p, a, 100.0), expected, 1e-9);
  }
}

TEST(SimWorldTest, RaysAlongTheAxes) {
  const Room room = MakeRoom(100, 60);
  const SimWorld world(room.grid);
  const Point2d p{room.x_min + 1.234, room.y_min + 0.777};
  EXPECT_NEAR(world.CastRayAlong(p, {1.0, 0.0}, 100.0), room.x_max - p.x_m, 1e-12);
  EXPECT_NEAR(world.CastRayAlong(p, {-1.0, 0.0}, 100.0), p.x_m - room.x_min, 1e-12);
  EXPECT_NEAR(world.CastRayAlong(p, {0.0, 1.0}, 100.0), room.y_max - p.y_m, 1e-12);
  EXPECT_NEAR(world.CastRayAlong(p, {0.0, -1.0}, 100.0), p.y_m - room.y_min, 1e-12);
  EXPECT_NEAR(world.CastRay(p, 0.0, 100.0), room.x_max - p.x_m, 1e-12);
  EXPECT_NEAR(world.CastRay(p, M_PI / 2, 100.0), room.y_max - p.y_m, 1e-9);
  EXPECT_NEAR(world.CastRay(p, M_PI, 100.0), p.x_m - room.x_min, 1e-9);
  EXPECT_NEAR(world.CastRay(p, -M_PI / 2, 100.0), p.y_m - room.y_min, 1e-9);
}

// Coordinates exactly on cell boundaries need a binary-exact grid.
TEST(SimWorldTest, RaysOnCellBoundaries) {
  const Room room = MakeRoom(64, 32, 0.125, {-2.0, 1.0});
  const SimWorld world(room.grid);
  // Along the boundary line between the bottom wall and the first free row:
  // the start cell is the free one above, and the ray never enters the wall.
  const Point2d on_line{room.x_min + 0.5, room.y_min};
  EXPECT_EQ(world.CastRayAlong(on_line, {1.0, 0.0}, 100.0), room.x_max - on_line.x_m);
  EXPECT_EQ(world.CastRayAlong(on_line, {-1.0, 0.0}, 100.0), 0.5);
  EXPECT_EQ(world.CastRayAlong(on_line, {0.0, -1.0}, 100.0), 0.0);  // straight into the wall
  EXPECT_EQ(world.CastRayAlong(on_line, {0.0, 1.0}, 100.0), room.y_max - room.y_min);
  // Through cell corners on the diagonal: the walls are hit at the analytic point.
  const Point2d corner{room.x_min + 1.0, room.y_min + 1.0};
  EXPECT_NEAR(world.CastRay(corner, -3 * M_PI / 4, 100.0), 1.0 * M_SQRT2, 1e-12);
  EXPECT_NEAR(world.CastRayPlain(corner, -3 * M_PI / 4, 100.0), 1.0 * M_SQRT2, 1e-12);
  // On the wall face, looking into the wall.
  EXPECT_EQ(world.CastRayAlong({room.x_min, room.y_min + 0.5}, {-1.0, 0.0}, 10.0), 0.0);
}

TEST(SimWorldTest, RayStartingInASolidCellOrOffTheMapIsZero) {
  const Room room = MakeRoom(40, 40);
  const SimWorld world(room.grid);
  const Point2d in_wall{room.x_min - 0.5 * kResolutionM, room.y_min + 0.5};
  for (double a : {0.0, 1.0, M_PI, -2.0}) {
    EXPECT_EQ(world.CastRay(in_wall, a, 10.0), 0.0);
    EXPECT_EQ(world.CastRayPlain(in_wall, a, 10.0), 0.0);
  }
  EXPECT_EQ(world.CastRay({-100.0, 0.0}, 0.0, 1000.0), 0.0);
  EXPECT_EQ(world.CastRay({std::nan(""), 3.0}, 0.0, 1000.0), 0.0);
}

TEST(SimWorldTest, MaxRangeReportsNoHit) {
  const Room room = MakeRoom(200, 40);
  const SimWorld world(room.grid);
  const Point2d p{room.x_min + 1.0, room.y_min + 1.0};
  const double to_wall = room.x_max - p.x_m;
  EXPECT_EQ(world.CastRayAlong(p, {1.0, 0.0}, to_wall - 0.01), SimWorld::kNoHit);
  EXPECT_EQ(world.CastRayAlongPlain(p, {1.0, 0.0}, to_wall - 0.01), SimWorld::kNoHit);
  EXPECT_NEAR(world.CastRayAlong(p, {1.0, 0.0}, to_wall + 0.01), to_wall, 1e-12);
  EXPECT_NEAR(world.CastRayAlong(p, {1.0, 0.0}, SimWorld::kNoHit), to_wall, 1e-12);
}

// Random blocks, scattered cells, unknown patches and free space.
OccupancyGrid RandomObstacleGrid(uint64_t seed) {
  std::mt19937_64 rng(seed);
  OccupancyGrid grid(310, 247, 0.05, {-3.0, 1.0}, OccupancyGrid::kFree);
  std::uniform_int_distribution<int> col(0, grid.width_cells() - 1);
  std::uniform_int_distribution<int> row(0, grid.height_cells() - 1);
  std::uniform_int_distribution<int> size(1, 25);
  std::uniform_int_distribution<int> value(-1, 100);
  for (int block = 0; block < 60; ++block) {
    const int c0 = col(rng), r0 = row(rng), w = size(rng), h = size(rng);
    const int8_t v = static_cast<int8_t>(value(rng) == 0 ? 100 : value(rng));
    for (int r = r0; r < std::min(r0 + h, grid.height_cells()); ++r) {
      for (int c = c0; c < std::min(c0 + w, grid.width_cells()); ++c) grid.at({c, r}) = v;
    }
  }
  for (int i = 0; i < 800; ++i) grid.at({col(rng), row(rng)}) = OccupancyGrid::kOccupied;
  return grid;
}

TEST(SimWorldTest, DistanceFieldCastEqualsPlainTraversalExactly) {
  const OccupancyGrid grid = RandomObstacleGrid(42);
  const SimWorld world(grid);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(grid.origin_m().x_m - 0.2,
                                            grid.origin_m().x_m + grid.width_m() + 0.2);
  std::uniform_real_distribution<double> uy(grid.origin_m().y_m - 0.2,
                                            grid.origin_m().y_m + grid.height_m() + 0.2);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_real_distribution<double> range(0.0, 25.0);
  std::uniform_int_distribution<int> kind(0, 3);
  int hits = 0, long_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Point2d p{ux(rng), uy(rng)};
    double a = angle(rng);
    switch (kind(rng)) {
      case 0:  // from a cell corner along a diagonal: ties between the axes
        p = {grid.origin_m().x_m + std::round((p.x_m - grid.origin_m().x_m) / 0.05) * 0.05,
             grid.origin_m().y_m + std::round((p.y_m - grid.origin_m().y_m) / 0.05) * 0.05};
        a = std::round(a / (M_PI / 4)) * (M_PI / 4);
        break;
      case 1:  // exact axis directions
        a = std::round(a / (M_PI / 2)) * (M_PI / 2);
        break;
      default: break;
    }
    const double max_range = i % 5 == 0 ? SimWorld::kNoHit : range(rng);
    const double fast = world.CastRay(p, a, max_range);
    const double plain = world.CastRayPlain(p, a, max_range);
    ASSERT_EQ(fast, plain) << "ray " << i << " from (" << p.x_m << ", " << p.y_m << ") at " << a
                           << " max " << max_range;
    hits += fast > 0.0 && fast != SimWorld::kNoHit;
    long_hits += fast > 3.0 && fast != SimWorld::kNoHit;
  }
  EXPECT_GT(hits, 5000);  // the test exercised real traversals, not just rays from walls
  EXPECT_GT(long_hits, 1000);
}

TEST(SimWorldTest, BatchCastEqualsSingleRays) {
  const OccupancyGrid grid = RandomObstacleGrid(21);
  const SimWorld world(grid);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> ux(grid.origin_m().x_m,
                                            grid.origin_m().x_m + grid.width_m());
  std::uniform_real_distribution<double> uy(grid.origin_m().y_m,
                                            grid.origin_m().y_m + grid.height_m());
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  int compared = 0;
  for (int sweep = 0; sweep < 400; ++sweep) {
    const Point2d origin{ux(rng), uy(rng)};
    // Lidar-like sweeps (ordered beams hand free discs on) and random directions.
    std::vector<Point2d> directions;
    const int beams = 1 + (sweep * 37) % 1000;
    const double start = angle(rng);
    for (int i = 0; i < beams; ++i) {
      const double a = sweep % 4 == 3 ? angle(rng) : start + i * 2 * M_PI / beams;
      directions.push_back({std::cos(a), std::sin(a)});
    }
    const double max_range = sweep % 3 == 0 ? SimWorld::kNoHit : 2.0 + sweep % 13;
    const std::vector<double> ranges = world.CastRays(origin, directions, max_range);
    ASSERT_EQ(ranges.size(), directions.size());
    for (std::size_t i = 0; i < directions.size(); ++i) {
      ASSERT_EQ(ranges[i], world.CastRayAlongPlain(origin, directions[i], max_range))
          << "sweep " << sweep << " beam " << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 100000);
  EXPECT_TRUE(world.CastRays({0.0, 0.0}, {}, 1.0).empty());
}

TEST(SimWorldTest, SafeSkipIsALowerBoundOnTheDistanceToSolidCells) {
  const OccupancyGrid grid = RandomObstacleGrid(5);
  const SimWorld world(grid);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> col(0, grid.width_cells() - 1);
  std::uniform_int_distribution<int> row(0, grid.height_cells() - 1);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const CellIndex cell{col(rng), row(rng)};
    const int skip = world.SafeSkipCells(cell);
    if (skip <= 0) continue;
    ++checked;
    // Square-to-square distance to every solid cell (including the outside ring) exceeds skip.
    for (int r = -1; r <= grid.height_cells(); ++r) {
      for (int c = -1; c <= grid.width_cells(); ++c) {
        if (!world.IsSolid({c, r})) continue;
        const double gap_x = std::max(std::abs(c - cell.col) - 1, 0);
        const double gap_y = std::max(std::abs(r - cell.row) - 1, 0);
        ASSERT_GT(std::hypot(gap_x, gap_y), skip);
      }
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(SimWorldTest, CircleAgainstAWallAndACorner) {
  OccupancyGrid grid(40, 40, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  grid.at({20, 20}) = OccupancyGrid::kOccupied;  // the square [2, 2.1] x [2, 2.1]
  const SimWorld world(grid);
  const double r = 0.3;
  EXPECT_FALSE(world.CircleCollides({2.05, 2.1 + r + 1e-6}, r));
  EXPECT_TRUE(world.CircleCollides({2.05, 2.1 + r - 1e-6}, r));
  EXPECT_FALSE(world.CircleCollides({2.0 - r - 1e-6, 2.05}, r));
  EXPECT_TRUE(world.CircleCollides({2.0 - r + 1e-6, 2.05}, r));
  // Diagonally off the corner (2.1, 2.1): the bounding boxes overlap, the disc does not.
  const double d = (r + 1e-6) / M_SQRT2;
  EXPECT_FALSE(world.CircleCollides({2.1 + d, 2.1 + d}, r));
  const double e = (r - 1e-6) / M_SQRT2;
  EXPECT_TRUE(world.CircleCollides({2.1 + e, 2.1 + e}, r));
  // Inside the cell, off the map, next to the map edge.
  EXPECT_TRUE(world.CircleCollides({2.05, 2.05}, 0.01));
  EXPECT_TRUE(world.CircleCollides({-1.0, 1.0}, 0.1));
  EXPECT_TRUE(world.CircleCollides({0.2, 1.0}, 0.21));
  EXPECT_FALSE(world.CircleCollides({0.2, 1.0}, 0.19));
}

TEST(SimWorldTest, CircleMatchesBruteForce) {
  const OccupancyGrid grid = RandomObstacleGrid(9);
  const SimWorld world(grid);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> ux(grid.origin_m().x_m,
                                            grid.origin_m().x_m + grid.width_m());
  std::uniform_real_distribution<double> uy(grid.origin_m().y_m,
                                            grid.origin_m().y_m + grid.height_m());
  std::uniform_real_distribution<double> radius(0.01, 0.6);
  int collisions = 0;
  for (int i = 0; i < 1000; ++i) {
    const Point2d p{ux(rng), uy(rng)};
    const double r = radius(rng);
    double nearest_m = std::numeric_limits<double>::infinity();
    for (int row = -1; row <= grid.height_cells(); ++row) {
      for (int col = -1; col <= grid.width_cells(); ++col) {
        if (!world.IsSolid({col, row})) continue;
        const double x0 = grid.origin_m().x_m + col * 0.05, y0 = grid.origin_m().y_m + row * 0.05;
        const double qx = std::clamp(p.x_m, x0, x0 + 0.05), qy = std::clamp(p.y_m, y0, y0 + 0.05);
        nearest_m = std::min(nearest_m, std::hypot(qx - p.x_m, qy - p.y_m));
      }
    }
    if (std::abs(nearest_m - r) < 1e-9) continue;  // too close to call with rounding
    EXPECT_EQ(world.CircleCollides(p, r), nearest_m < r) << i;
    collisions += nearest_m < r;
  }
  EXPECT_GT(collisions, 100);
  EXPECT_LT(collisions, 900);
}

}  // namespace
}  // namespace aslam
