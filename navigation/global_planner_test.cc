#include "navigation/global_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/world_file.h"
#include "navigation/costmap.h"

namespace aslam {
namespace {

constexpr double kRes = 0.05;
constexpr double kInf = std::numeric_limits<double>::infinity();

OccupancyGrid RandomGrid(std::mt19937& rng, int width, int height, double obstacle_p,
                         double unknown_p) {
  OccupancyGrid grid(width, height, kRes, {1.0, -2.0});
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int8_t& value : grid.mutable_cells()) {
    const double draw = u01(rng);
    if (draw < obstacle_p) {
      value = OccupancyGrid::kOccupied;
    } else if (draw < obstacle_p + unknown_p) {
      value = OccupancyGrid::kUnknown;
    } else {
      value = OccupancyGrid::kFree;
    }
  }
  return grid;
}

// Edge cost exactly as documented in global_planner.h, in double; +inf when
// the step is not allowed (target not traversable, or a diagonal cutting a corner).
double EdgeCost(const Costmap& costmap, const GlobalPlannerOptions& options, CellIndex from,
                CellIndex to) {
  const int dc = to.col - from.col;
  const int dr = to.row - from.row;
  if (!costmap.Traversable(to)) return kInf;
  if (dc != 0 && dr != 0 &&
      (!costmap.Traversable({from.col + dc, from.row}) ||
       !costmap.Traversable({from.col, from.row + dr}))) {
    return kInf;
  }
  const double step = (dc != 0 && dr != 0) ? std::sqrt(2.0) : 1.0;
  const double c = costmap.cost(to) + (costmap.IsUnknown(to) ? costmap.options().unknown_cost : 0);
  return step * (1.0 + options.cost_weight * c / 253.0);
}

// Bellman-Ford over all 8-neighbour edges until nothing changes.
std::vector<double> BruteForceCosts(const Costmap& costmap, const GlobalPlannerOptions& options,
                                    CellIndex start) {
  const int w = costmap.width_cells();
  const int h = costmap.height_cells();
  std::vector<double> dist(static_cast<std::size_t>(w) * h, kInf);
  dist[costmap.LinearIndex(start)] = 0.0;
  for (bool changed = true; changed;) {
    changed = false;
    for (int row = 0; row < h; ++row) {
      for (int col = 0; col < w; ++col) {
        const double du = dist[costmap.LinearIndex({col, row})];
        if (du == kInf) continue;
        for (int dr = -1; dr <= 1; ++dr) {
          for (int dc = -1; dc <= 1; ++dc) {
            const CellIndex to{col + dc, row + dr};
            if ((dc == 0 && dr == 0) || !costmap.Contains(to)) continue;
            const double candidate = du + EdgeCost(costmap, options, {col, row}, to);
            double& dv = dist[costmap.LinearIndex(to)];
            if (candidate < dv - 1e-12) {
              dv = candidate;
              changed = true;
            }
          }
        }
      }
    }
  }
  return dist;
}

CellIndex RandomTraversableCell(std::mt19937& rng, const Costmap& costmap) {
  std::uniform_int_distribution<int> col(0, costmap.width_cells() - 1);
  std::uniform_int_distribution<int> row(0, costmap.height_cells() - 1);
  for (int attempt = 0; attempt < 10000; ++attempt) {
    const CellIndex cell{col(rng), row(rng)};
    if (costmap.Traversable(cell)) return cell;
  }
  return {-1, -1};
}

// A random costmap with small inflation so that it has varied costs and open space.
Costmap RandomCostmap(int seed, int width, int height) {
  std::mt19937 rng(seed);
  const OccupancyGrid grid = RandomGrid(rng, width, height, 0.04 + 0.02 * (seed % 5), 0.15);
  CostmapOptions options;
  options.robot_radius_m = (seed % 3) * 0.03;  // 0, 0.03 or 0.06 m
  options.inflation_margin_m = 0.05 + 0.05 * (seed % 4);
  options.cost_scaling_per_m = 3.0 + seed % 5;
  options.unknown_passable = seed % 4 != 0;
  options.unknown_cost = (seed * 37) % 200;
  return Costmap(grid, options);
}

// Without the start escape: the references below know only the documented edges (random grids
// shut many starts in small pockets); the escape has its own tests.
GlobalPlannerOptions RandomPlannerOptions(int seed) {
  GlobalPlannerOptions options;
  const double weights[] = {0.0, 1.0, 3.0, 10.0};
  options.cost_weight = weights[seed % 4];
  options.start_escape_m = 0.0;
  return options;
}

// Checks a path: an 8-connected chain from start to goal through traversable
// cells without corner cutting, its length and cost recomputed plainly.
void ExpectValidPath(const Costmap& costmap, const GlobalPlannerOptions& options,
                     const GlobalPath& path, CellIndex start, CellIndex goal,
                     const std::string& where) {
  ASSERT_FALSE(path.cells.empty()) << where;
  EXPECT_EQ(path.cells.front(), start) << where;
  EXPECT_EQ(path.cells.back(), goal) << where;
  ASSERT_EQ(path.points_m.size(), path.cells.size()) << where;
  double length_m = 0.0;
  double cost = 0.0;
  for (std::size_t i = 0; i < path.cells.size(); ++i) {
    const CellIndex cell = path.cells[i];
    const Point2d centre = costmap.CellCenter(cell);
    EXPECT_DOUBLE_EQ(path.points_m[i].x_m, centre.x_m) << where;
    EXPECT_DOUBLE_EQ(path.points_m[i].y_m, centre.y_m) << where;
    if (i == 0) continue;
    const CellIndex prev = path.cells[i - 1];
    const int dc = cell.col - prev.col;
    const int dr = cell.row - prev.row;
    ASSERT_TRUE(std::abs(dc) <= 1 && std::abs(dr) <= 1 && (dc != 0 || dr != 0))
        << where << ": step " << i << " is not to an 8-neighbour";
    ASSERT_TRUE(costmap.Traversable(cell)) << where << ": step " << i;
    if (dc != 0 && dr != 0) {
      ASSERT_TRUE(costmap.Traversable({prev.col + dc, prev.row}) &&
                  costmap.Traversable({prev.col, prev.row + dr}))
          << where << ": step " << i << " cuts a corner";
    }
    length_m += std::hypot(dc, dr) * costmap.resolution_m();
    cost += EdgeCost(costmap, options, prev, cell);
  }
  EXPECT_NEAR(path.length_m, length_m, 1e-5 * (1.0 + length_m)) << where;
  EXPECT_NEAR(path.cost, cost, 1e-5 * (1.0 + cost)) << where;
}

TEST(GlobalPlannerTest, DijkstraEqualsBellmanFordOnRandomGrids) {
  int reachable_checked = 0;
  for (int seed = 0; seed < 200; ++seed) {
    // Many small grids (every corner case of the border), then larger ones
    // where long detours compete.
    const bool large = seed >= 150;
    const Costmap costmap = large ? RandomCostmap(seed, 45, 35)
                                  : RandomCostmap(seed, 4 + seed % 13, 3 + (seed * 5) % 14);
    const GlobalPlannerOptions options = RandomPlannerOptions(seed);
    std::mt19937 rng(seed);
    const CellIndex start = RandomTraversableCell(rng, costmap);
    if (start.col < 0) continue;
    const ShortestPathTree tree = GlobalPlanner(options).Search(costmap, start);
    const std::vector<double> expected = BruteForceCosts(costmap, options, start);
    std::size_t reachable = 0;
    for (int row = 0; row < costmap.height_cells(); ++row) {
      for (int col = 0; col < costmap.width_cells(); ++col) {
        const CellIndex cell{col, row};
        const double want = expected[costmap.LinearIndex(cell)];
        const std::string where = "seed " + std::to_string(seed) + " cell " + std::to_string(col) +
                                  "," + std::to_string(row);
        ASSERT_EQ(tree.Reachable(cell), want != kInf) << where;
        if (want == kInf) {
          EXPECT_EQ(tree.CostTo(cell), kInf) << where;
          EXPECT_EQ(tree.PathLengthM(cell), kInf) << where;
          EXPECT_FALSE(tree.PathTo(cell).has_value()) << where;
          continue;
        }
        ++reachable;
        ASSERT_NEAR(tree.CostTo(cell), want, 1e-5 * (1.0 + want)) << where;
        const auto path = tree.PathTo(cell);
        ASSERT_TRUE(path.has_value()) << where;
        ExpectValidPath(costmap, options, *path, start, cell, where);
        EXPECT_DOUBLE_EQ(path->length_m, tree.PathLengthM(cell)) << where;
      }
    }
    EXPECT_EQ(tree.settled_count(), reachable);
    reachable_checked += static_cast<int>(reachable);
  }
  EXPECT_GT(reachable_checked, 15000);
}

// Plan is an A* search: its paths must cost exactly what the one-to-all search says, on the
// octile heuristic and on a goal-distance field of the same costmap.
TEST(GlobalPlannerTest, PlanCostsEqualBellmanFordOnRandomGrids) {
  int planned = 0;
  for (int seed = 0; seed < 120; ++seed) {
    const Costmap costmap = seed < 60 ? RandomCostmap(900 + seed, 3 + seed % 17, 3 + seed % 11)
                                      : RandomCostmap(900 + seed, 50, 40);
    const GlobalPlannerOptions options = RandomPlannerOptions(seed);
    const GlobalPlanner planner(options);
    std::mt19937 rng(seed);
    const CellIndex start = RandomTraversableCell(rng, costmap);
    if (start.col < 0) continue;
    const std::vector<double> expected = BruteForceCosts(costmap, options, start);
    ShortestPathTree scratch;
    for (int k = 0; k < 5; ++k) {
      const CellIndex goal = RandomTraversableCell(rng, costmap);
      const std::string where = "seed " + std::to_string(seed) + " goal " +
                                std::to_string(goal.col) + "," + std::to_string(goal.row);
      const double want = expected[costmap.LinearIndex(goal)];
      ShortestPathTree field;
      // The field may be made from elsewhere than the plan's start (the robot moves on).
      const CellIndex field_robot = k % 2 == 0 ? start : RandomTraversableCell(rng, costmap);
      planner.DistancesToGoal(costmap, goal, field_robot, &field);
      for (const ShortestPathTree* heuristic : {static_cast<ShortestPathTree*>(nullptr), &field}) {
        const auto path = planner.Plan(costmap, costmap.CellCenter(start), costmap.CellCenter(goal),
                                       k % 2 == 0 ? &scratch : nullptr, heuristic);
        const std::string how = where + (heuristic ? " on the field" : " on octile");
        ASSERT_EQ(path.has_value(), want != kInf) << how;
        if (!path) continue;
        EXPECT_NEAR(path->cost, want, 1e-5 * (1.0 + want)) << how;
        ExpectValidPath(costmap, options, *path, start, goal, how);
        ++planned;
      }
    }
  }
  EXPECT_GT(planned, 500);
}

// Towards one goal in the open, A* settles a narrow band, not the disc Dijkstra settles.
TEST(GlobalPlannerTest, PlanSettlesFewCellsTowardsItsGoal) {
  const OccupancyGrid grid(200, 200, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  const Costmap costmap(grid, CostmapOptions{});
  const GlobalPlanner planner;
  const CellIndex start{20, 100};
  const CellIndex goal{180, 100};
  ShortestPathTree plan_tree;
  const auto path =
      planner.Plan(costmap, costmap.CellCenter(start), costmap.CellCenter(goal), &plan_tree);
  ASSERT_TRUE(path.has_value());
  EXPECT_NEAR(path->length_m, 160 * 0.05, 1e-5);
  const ShortestPathTree dijkstra = planner.Search(costmap, start, {goal});
  EXPECT_EQ(dijkstra.CostTo(goal), path->cost);
  EXPECT_LT(plan_tree.settled_count() * 5, dijkstra.settled_count());
}

// The field never exceeds the cost of a path to the goal: it is a lower bound.
TEST(GlobalPlannerTest, GoalFieldIsALowerBoundOnEveryPathCost) {
  for (int seed = 0; seed < 30; ++seed) {
    const Costmap costmap = RandomCostmap(500 + seed, 20, 15);
    const GlobalPlannerOptions options = RandomPlannerOptions(seed);
    std::mt19937 rng(seed);
    const CellIndex goal = RandomTraversableCell(rng, costmap);
    if (goal.col < 0) continue;
    ShortestPathTree field;
    GlobalPlanner(options).DistancesToGoal(costmap, goal, goal, &field);
    // Costs to the goal = costs from it with every edge reversed: one search per start.
    for (int row = 0; row < costmap.height_cells(); ++row) {
      for (int col = 0; col < costmap.width_cells(); ++col) {
        const CellIndex cell{col, row};
        if (!costmap.Traversable(cell)) continue;
        const double to_goal = BruteForceCosts(costmap, options, cell)[costmap.LinearIndex(goal)];
        if (to_goal == kInf || !field.Reachable(cell)) continue;
        EXPECT_LE(field.CostTo(cell), to_goal * (1.0 + 1e-6))
            << "seed " << seed << " cell " << col << "," << row;
      }
    }
  }
}

// On a real floor the field guides A* along the corridors: the same costs, far fewer cells.
TEST(GlobalPlannerTest, CampusPlansOnAGoalFieldSettleFewerCellsForTheSameCost) {
  const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus");
  const Costmap costmap(world.map.grid, CostmapOptions{});
  const GlobalPlanner planner;
  const Point2d start_m{world.start.x_m, world.start.y_m};
  const CellIndex start = costmap.WorldToCell(start_m);
  std::mt19937 rng(11);
  std::size_t settled_octile = 0, settled_field = 0;
  int planned = 0;
  while (planned < 6) {
    const CellIndex goal = RandomTraversableCell(rng, costmap);
    ShortestPathTree octile_tree, field_tree, field;
    const auto octile = planner.Plan(costmap, start_m, costmap.CellCenter(goal), &octile_tree);
    if (!octile) continue;
    planner.DistancesToGoal(costmap, goal, start, &field);
    const auto guided =
        planner.Plan(costmap, start_m, costmap.CellCenter(goal), &field_tree, &field);
    ASSERT_TRUE(guided.has_value());
    EXPECT_NEAR(guided->cost, octile->cost, 1e-5 * octile->cost);
    ExpectValidPath(costmap, planner.options(), *guided, start, goal, "campus");
    settled_octile += octile_tree.settled_count();
    settled_field += field_tree.settled_count();
    ++planned;
  }
  EXPECT_LT(settled_field * 3, settled_octile);
}

// A field from an older map: walls added since keep plans the cheapest; where walls have gone
// the plan is still a valid path, and a field for another goal or grid is not used at all.
TEST(GlobalPlannerTest, StaleOrForeignGoalFieldsStillGiveValidPaths) {
  int compared = 0;
  for (int seed = 0; seed < 150; ++seed) {
    std::mt19937 rng(seed);
    const OccupancyGrid before = RandomGrid(rng, 40, 30, 0.04, 0.1);
    OccupancyGrid added = before, changed = before;
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (std::size_t i = 0; i < before.cells().size(); ++i) {
      const double draw = u01(rng);
      if (draw < 0.05) {
        added.mutable_cells()[i] = changed.mutable_cells()[i] = OccupancyGrid::kOccupied;
      } else if (draw < 0.10 && before.cells()[i] == OccupancyGrid::kOccupied) {
        changed.mutable_cells()[i] = OccupancyGrid::kFree;  // a wall gone
      }
    }
    CostmapOptions costmap_options;
    costmap_options.inflation_margin_m = 0.1;
    const Costmap old_costmap(before, costmap_options);
    const GlobalPlanner planner(RandomPlannerOptions(seed));
    for (const OccupancyGrid* now : {&added, &changed}) {
      const Costmap costmap(*now, costmap_options);
      const CellIndex start = RandomTraversableCell(rng, costmap);
      const CellIndex goal = RandomTraversableCell(rng, costmap);
      if (start.col < 0 || goal.col < 0 || !old_costmap.Traversable(goal)) continue;
      const std::string where = "seed " + std::to_string(seed);
      ShortestPathTree stale, foreign, fresh_tree, stale_tree, foreign_tree;
      planner.DistancesToGoal(old_costmap, goal, start, &stale);
      planner.DistancesToGoal(costmap, start, goal, &foreign);  // towards another cell
      const Point2d start_m = costmap.CellCenter(start), goal_m = costmap.CellCenter(goal);
      const auto fresh = planner.Plan(costmap, start_m, goal_m, &fresh_tree);
      const auto on_stale = planner.Plan(costmap, start_m, goal_m, &stale_tree, &stale);
      const auto on_foreign = planner.Plan(costmap, start_m, goal_m, &foreign_tree, &foreign);
      ASSERT_EQ(on_stale.has_value(), fresh.has_value()) << where;
      ASSERT_EQ(on_foreign.has_value(), fresh.has_value()) << where;
      if (!fresh) continue;
      ExpectValidPath(costmap, planner.options(), *on_stale, start, goal, where);
      EXPECT_GE(on_stale->cost, fresh->cost * (1.0 - 1e-6)) << where;
      if (now == &added) {
        EXPECT_NEAR(on_stale->cost, fresh->cost, 1e-5 * fresh->cost) << where;
      }
      EXPECT_EQ(on_foreign->cost, fresh->cost) << where;
      EXPECT_EQ(foreign_tree.settled_count(), fresh_tree.settled_count()) << where;
      ++compared;
    }
  }
  EXPECT_GT(compared, 100);
}

TEST(GlobalPlannerTest, ManyTargetsSearchEqualsOneSearchPerTarget) {
  for (int seed = 0; seed < 12; ++seed) {
    const Costmap costmap = RandomCostmap(500 + seed, 60, 45);
    const GlobalPlannerOptions options = RandomPlannerOptions(seed);
    const GlobalPlanner planner(options);
    std::mt19937 rng(seed);
    const CellIndex start = RandomTraversableCell(rng, costmap);
    ASSERT_GE(start.col, 0);
    std::vector<CellIndex> targets;
    for (int i = 0; i < 15; ++i) targets.push_back(RandomTraversableCell(rng, costmap));
    targets.push_back({0, 0});      // any cell, traversable or not
    targets.push_back(targets[0]);  // a duplicate
    targets.push_back({-3, 2});     // off the map

    const ShortestPathTree many = planner.Search(costmap, start, targets);
    const ShortestPathTree all = planner.Search(costmap, start);
    ShortestPathTree reused;
    for (const CellIndex& target : targets) {
      const std::string where = "seed " + std::to_string(seed);
      planner.Search(costmap, start, {target}, &reused);
      const ShortestPathTree single = planner.Search(costmap, start, {target});
      for (const ShortestPathTree* one :
           {&single, static_cast<const ShortestPathTree*>(&reused), &all}) {
        EXPECT_EQ(many.Reachable(target), one->Reachable(target)) << where;
        EXPECT_EQ(many.CostTo(target), one->CostTo(target)) << where;
        EXPECT_EQ(many.PathLengthM(target), one->PathLengthM(target)) << where;
      }
      const auto plan =
          planner.Plan(costmap, costmap.CellCenter(start), costmap.CellCenter(target));
      ASSERT_EQ(plan.has_value(), many.Reachable(target) && costmap.Traversable(target)) << where;
      if (!plan) continue;
      const auto path = many.PathTo(target);
      ASSERT_TRUE(path.has_value());
      EXPECT_EQ(plan->cost, path->cost) << where;
      EXPECT_EQ(plan->length_m, path->length_m) << where;
      EXPECT_EQ(plan->cells.size(), path->cells.size()) << where;
      ExpectValidPath(costmap, options, *plan, start, target, where);
    }
  }
}

TEST(GlobalPlannerTest, SearchStopsOnceAllTargetsAreSettled) {
  OccupancyGrid grid(80, 80, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  const Costmap costmap(grid, CostmapOptions{});
  const GlobalPlanner planner;
  const ShortestPathTree full = planner.Search(costmap, {40, 40});
  const ShortestPathTree near = planner.Search(costmap, {40, 40}, {{42, 41}, {38, 40}});
  EXPECT_EQ(full.settled_count(), 80u * 80u);
  EXPECT_LT(near.settled_count(), 100u);
  EXPECT_TRUE(near.Reachable({42, 41}));
  EXPECT_TRUE(near.Reachable({38, 40}));
  EXPECT_FALSE(near.Reachable({0, 0}));  // beyond the targets: not settled
  EXPECT_EQ(near.CostTo({0, 0}), kInf);
  // An unreachable target cannot stop the search early.
  grid.at({5, 5}) = OccupancyGrid::kOccupied;
  const Costmap walled(grid, CostmapOptions{});
  const ShortestPathTree blocked = planner.Search(walled, {40, 40}, {{5, 5}});
  EXPECT_FALSE(blocked.Reachable({5, 5}));
  EXPECT_TRUE(blocked.Reachable({0, 79}));
}

// A 6 m x 3 m room with a wall down the middle that has a door at the top.
OccupancyGrid RoomWithWall() {
  OccupancyGrid grid(120, 60, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int i = 0; i < 120; ++i) {
    grid.at({i, 0}) = grid.at({i, 59}) = OccupancyGrid::kOccupied;
  }
  for (int j = 0; j < 60; ++j) {
    grid.at({0, j}) = grid.at({119, j}) = OccupancyGrid::kOccupied;
    if (j < 40) grid.at({60, j}) = OccupancyGrid::kOccupied;
  }
  return grid;
}

TEST(GlobalPlannerTest, PlanGoesAroundTheWallAndRefusesGoalsInWalls) {
  const OccupancyGrid grid = RoomWithWall();
  const Costmap costmap(grid, CostmapOptions{});
  const GlobalPlanner planner;
  const Point2d start{1.0, 1.0};
  const auto path = planner.Plan(costmap, start, {5.0, 1.0});
  ASSERT_TRUE(path.has_value());
  // Up through the door (y >= 2 m) and down again: longer than the 4 m straight line.
  EXPECT_GT(path->length_m, 2.0 * std::hypot(2.0, 1.0 + 0.2));
  double max_y = 0.0;
  for (const Point2d& p : path->points_m) max_y = std::max(max_y, p.y_m);
  EXPECT_GT(max_y, 2.0);
  ExpectValidPath(costmap, planner.options(), *path, costmap.WorldToCell(start),
                  costmap.WorldToCell({5.0, 1.0}), "room");

  EXPECT_FALSE(planner.Plan(costmap, start, {3.02, 1.0}).has_value());       // in the wall
  EXPECT_FALSE(planner.Plan(costmap, start, {3.2, 1.0}).has_value());        // inscribed
  EXPECT_FALSE(planner.Plan(costmap, start, {30.0, 1.0}).has_value());       // off the map
  EXPECT_FALSE(planner.Plan(costmap, {-1.0, 1.0}, {5.0, 1.0}).has_value());  // start off the map
  EXPECT_TRUE(planner.Plan(costmap, start, start).has_value());              // already there

  // Closing the door makes the other side unreachable.
  OccupancyGrid closed = grid;
  for (int j = 40; j < 60; ++j) closed.at({60, j}) = OccupancyGrid::kOccupied;
  const Costmap closed_costmap(closed, CostmapOptions{});
  EXPECT_TRUE(closed_costmap.Traversable(closed_costmap.WorldToCell({5.0, 1.0})));
  EXPECT_FALSE(planner.Plan(closed_costmap, start, {5.0, 1.0}).has_value());
}

// A goal the robot cannot stand on is approached from a reachable cell that sees it: never from
// across a wall, however near.
TEST(GlobalPlannerTest, AGoalIsSnappedOnlyToReachableCellsThatSeeIt) {
  OccupancyGrid grid = RoomWithWall();
  const Costmap open(grid, CostmapOptions{});
  const CellIndex goal = open.WorldToCell({3.125, 1.0});  // 0.1 m east of the wall
  ASSERT_FALSE(open.Traversable(goal));
  ASSERT_LT(open.cost(goal), Costmap::kLethal);
  const GlobalPlanner planner;
  const CellIndex west = open.WorldToCell({1.0, 1.0});
  const std::optional<CellIndex> snapped =
      ReachableGoalCell(planner.Search(open, west), goal, GoalSnapCandidates(open, goal, 0.5));
  ASSERT_TRUE(snapped.has_value());
  EXPECT_GT(open.CellCenter(*snapped).x_m, 3.05);  // east of the wall: through the door
  EXPECT_LE(std::hypot(snapped->col - goal.col, snapped->row - goal.row) * kRes, 0.25);
  for (const CellIndex& cell : GoalSnapCandidates(open, goal, 0.5)) {
    EXPECT_TRUE(open.Traversable(cell));
    EXPECT_GT(open.CellCenter(cell).x_m, 3.05);
  }

  // A post 0.25 m east of the wall leaves the goal in a slot the robot does not fit; the free
  // cells 0.4 m west are across the wall, so nothing qualifies.
  for (int row = 10; row <= 30; ++row) grid.at({66, row}) = OccupancyGrid::kOccupied;
  const Costmap slot(grid, CostmapOptions{});
  ASSERT_TRUE(slot.Traversable(slot.WorldToCell({2.725, 1.0})));
  EXPECT_TRUE(GoalSnapCandidates(slot, goal, 0.5).empty());
  EXPECT_FALSE(
      ReachableGoalCell(planner.Search(slot, west), goal, GoalSnapCandidates(slot, goal, 0.5))
          .has_value());
}

TEST(GlobalPlannerTest, StartAgainstAWallEscapes) {
  const OccupancyGrid grid = RoomWithWall();
  const Costmap costmap(grid, CostmapOptions{});
  const Point2d start{2.925, 1.0};  // 0.1 m from the wall: inside the 0.2 m radius
  ASSERT_EQ(costmap.cost(costmap.WorldToCell(start)), Costmap::kInscribed);
  const GlobalPlanner planner;
  const auto path = planner.Plan(costmap, start, {1.0, 1.0});
  ASSERT_TRUE(path.has_value());
  const CellIndex start_cell = costmap.WorldToCell(start);
  // Only the escape leg may cross inscribed cells, and it stays near the start.
  for (const CellIndex& cell : path->cells) {
    if (!costmap.Traversable(cell)) {
      EXPECT_LE(std::hypot(cell.col - start_cell.col, cell.row - start_cell.row) * kRes,
                planner.options().start_escape_m + 1e-9);
    }
  }
  EXPECT_TRUE(costmap.Traversable(path->cells.back()));

  GlobalPlannerOptions no_escape;
  no_escape.start_escape_m = 0.0;
  EXPECT_FALSE(GlobalPlanner(no_escape).Plan(costmap, start, {1.0, 1.0}).has_value());

  // The escape only opens inscribed cells, never the wall: a start sealed in
  // by a ring of wall stays stuck even when the escape radius reaches past it.
  OccupancyGrid ring(40, 40, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int j = 0; j < 40; ++j) {
    for (int i = 0; i < 40; ++i) {
      if (std::max(std::abs(i - 20), std::abs(j - 20)) == 2)
        ring.at({i, j}) = OccupancyGrid::kOccupied;
    }
  }
  const Costmap ring_costmap(ring, CostmapOptions{});
  GlobalPlannerOptions wide_escape;
  wide_escape.start_escape_m = 0.5;  // 10 cells: well past the ring (2 cells away)
  EXPECT_FALSE(
      GlobalPlanner(wide_escape)
          .Plan(ring_costmap, ring_costmap.CellCenter({20, 20}), ring_costmap.CellCenter({2, 2}))
          .has_value());
  // Outside the ring, the same escape gets a robot off the ring's outer face.
  EXPECT_TRUE(
      GlobalPlanner(wide_escape)
          .Plan(ring_costmap, ring_costmap.CellCenter({20, 24}), ring_costmap.CellCenter({2, 2}))
          .has_value());
}

// Issue 15's dead-end pinch: the robot stands in a traversable pocket (here a 0.95 m x 0.75 m
// box with one 0.45 m gap) whose way out the inscribed zone closes. It must still plan out; a
// robot outside must still not plan in.
// A box of cols 40-60, rows 20-36 in open space, its west wall open at rows gap_first..gap_last.
OccupancyGrid BoxWithAGap(int gap_first_row, int gap_last_row) {
  OccupancyGrid grid(100, 60, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int col = 40; col <= 60; ++col) {
    grid.at({col, 20}) = OccupancyGrid::kOccupied;
    grid.at({col, 36}) = OccupancyGrid::kOccupied;
  }
  for (int row = 20; row <= 36; ++row) {
    grid.at({60, row}) = OccupancyGrid::kOccupied;
    if (row < gap_first_row || row > gap_last_row) grid.at({40, row}) = OccupancyGrid::kOccupied;
  }
  return grid;
}

TEST(GlobalPlannerTest, StartShutInAPocketEscapesThroughItsGap) {
  // Gap rows 24-32 (0.45 m): the robot's body fits, its clearance margin does not.
  const Costmap costmap(BoxWithAGap(24, 32), CostmapOptions{});
  const Point2d inside = costmap.CellCenter({50, 28});
  const Point2d outside = costmap.CellCenter({15, 28});
  ASSERT_TRUE(costmap.Traversable(costmap.WorldToCell(inside)));
  ASSERT_EQ(costmap.cost({40, 28}), Costmap::kInscribed);  // the gap: too narrow to plan through
  GlobalPlannerOptions no_escape;
  no_escape.start_escape_m = 0.0;
  ASSERT_FALSE(GlobalPlanner(no_escape).Plan(costmap, inside, outside).has_value());

  const GlobalPlanner planner;
  const auto out = planner.Plan(costmap, inside, outside);
  ASSERT_TRUE(out.has_value());
  // Inscribed cells only on the way out through the gap (its inscribed cells span cols 36-44).
  for (const CellIndex& cell : out->cells) {
    if (!costmap.Traversable(cell)) {
      EXPECT_GE(cell.col, 36);
      EXPECT_LE(cell.col, 44);
      EXPECT_LT(costmap.cost(cell), Costmap::kLethal);
    }
  }
  // The one search the utility and the frontier node run finds the outside reachable too.
  EXPECT_TRUE(planner.Search(costmap, costmap.WorldToCell(inside), {costmap.WorldToCell(outside)})
                  .Reachable(costmap.WorldToCell(outside)));
  // From the large free space, the pocket stays shut: no planning into a gap the robot does not
  // fit.
  EXPECT_FALSE(planner.Plan(costmap, outside, inside).has_value());
}

// The same box with a 0.25 m hole (a gap in a lidar-made wall): the robot's body does not fit,
// so the escape must not plan it out through the hole, nor call what lies beyond reachable.
TEST(GlobalPlannerTest, AHoleNarrowerThanTheRobotKeepsAPocketShut) {
  const Costmap costmap(BoxWithAGap(26, 30), CostmapOptions{});  // hole rows 26-30
  const Point2d inside = costmap.CellCenter({50, 28});
  const Point2d outside = costmap.CellCenter({15, 28});
  ASSERT_TRUE(costmap.Traversable(costmap.WorldToCell(inside)));
  ASSERT_LT(costmap.ObstacleDistanceM({40, 28}) - 0.5 * kRes, CostmapOptions{}.robot_radius_m);
  const GlobalPlanner planner;
  EXPECT_FALSE(planner.Plan(costmap, inside, outside).has_value());
  EXPECT_FALSE(planner.Search(costmap, costmap.WorldToCell(inside), {costmap.WorldToCell(outside)})
                   .Reachable(costmap.WorldToCell(outside)));
}

TEST(GlobalPlannerTest, UnknownCellsCostExtraOrBlock) {
  // A 3-row strip with one unknown column; no inflation, so costs are exact.
  OccupancyGrid grid(21, 3, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 3; ++row) grid.at({10, row}) = OccupancyGrid::kUnknown;
  CostmapOptions options;
  options.robot_radius_m = 0.0;
  options.inflation_margin_m = 0.0;
  options.unknown_cost = 50;
  const GlobalPlanner planner;  // cost_weight 3
  const Costmap passable(grid, options);
  const ShortestPathTree tree = planner.Search(passable, {0, 1});
  EXPECT_NEAR(tree.CostTo({20, 1}), 20.0 + 3.0 * 50.0 / 253.0, 1e-5);
  EXPECT_NEAR(tree.PathLengthM({20, 1}), 20 * kRes, 1e-6);
  EXPECT_NEAR(tree.CostTo({9, 1}), 9.0, 1e-6);

  options.unknown_cost = 0;
  EXPECT_NEAR(planner.Search(Costmap(grid, options), {0, 1}).CostTo({20, 1}), 20.0, 1e-5);

  options.unknown_passable = false;
  const Costmap closed(grid, options);
  EXPECT_FALSE(planner.Search(closed, {0, 1}).Reachable({20, 1}));
  EXPECT_FALSE(planner.Plan(closed, closed.CellCenter({0, 1}), closed.CellCenter({20, 1})));

  // With a known detour cheaper than the unknown penalty, the plan takes the detour.
  OccupancyGrid detour(21, 5, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 4; ++row) detour.at({10, row}) = OccupancyGrid::kUnknown;
  options.unknown_passable = true;
  options.unknown_cost = 252;
  GlobalPlannerOptions heavy;
  heavy.cost_weight = 50.0;
  const Costmap detour_costmap(detour, options);
  const auto path = GlobalPlanner(heavy).Plan(detour_costmap, detour_costmap.CellCenter({0, 0}),
                                              detour_costmap.CellCenter({20, 0}));
  ASSERT_TRUE(path.has_value());
  for (const CellIndex& cell : path->cells) EXPECT_FALSE(detour_costmap.IsUnknown(cell));
}

TEST(GlobalPlannerTest, CampusPlansEqualTheOneToAllSearch) {
  const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus");
  const Costmap costmap(world.map.grid, CostmapOptions{});
  const GlobalPlanner planner;
  const Point2d start_m{world.start.x_m, world.start.y_m};
  const CellIndex start = costmap.WorldToCell(start_m);
  const ShortestPathTree tree = planner.Search(costmap, start);
  EXPECT_GT(tree.settled_count(), 400000u);  // most of the ~2000 m2 of floor
  std::mt19937 rng(7);
  int planned = 0;
  while (planned < 4) {
    const CellIndex goal = RandomTraversableCell(rng, costmap);
    if (!tree.Reachable(goal)) continue;
    const auto plan = planner.Plan(costmap, start_m, costmap.CellCenter(goal));
    ASSERT_TRUE(plan.has_value());
    EXPECT_EQ(plan->cost, tree.CostTo(goal));
    EXPECT_EQ(plan->length_m, tree.PathLengthM(goal));
    ExpectValidPath(costmap, planner.options(), *plan, start, goal, "campus");
    // A path is never shorter than the straight line.
    EXPECT_GE(plan->length_m + 1e-9,
              std::hypot(goal.col - start.col, goal.row - start.row) * costmap.resolution_m());
    ++planned;
  }
}

TEST(GlobalPlannerTest, RejectsBadOptions) {
  GlobalPlannerOptions options;
  options.cost_weight = -1.0;
  EXPECT_THROW(GlobalPlanner{options}, std::invalid_argument);
  options.cost_weight = 3.0;
  options.start_escape_m = NAN;
  EXPECT_THROW(GlobalPlanner{options}, std::invalid_argument);
}

}  // namespace
}  // namespace aslam
