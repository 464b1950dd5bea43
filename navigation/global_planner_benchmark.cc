// Costmap construction, incremental costmap updates and Dijkstra on the
// campus world (0.05 m/cell) and a synthetic 1200 x 800-cell map.
//
//   build-gp/navigation/global_planner_benchmark

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "common/world_file.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"

namespace aslam {
namespace {

const WorldInfo& Campus() {
  static const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus");
  return world;
}

const Costmap& CampusCostmap() {
  static const Costmap costmap(Campus().map.grid, CostmapOptions{});
  return costmap;
}

CellIndex StartCell() {
  return CampusCostmap().WorldToCell({Campus().start.x_m, Campus().start.y_m});
}

// The traversable cell farthest (in path length) from the start: a plan across the building.
CellIndex FarthestCell() {
  static const CellIndex farthest = [] {
    const Costmap& costmap = CampusCostmap();
    const ShortestPathTree tree = GlobalPlanner().Search(costmap, StartCell());
    CellIndex best = StartCell();
    for (int row = 0; row < costmap.height_cells(); ++row) {
      for (int col = 0; col < costmap.width_cells(); ++col) {
        const CellIndex cell{col, row};
        if (tree.Reachable(cell) && tree.PathLengthM(cell) > tree.PathLengthM(best)) best = cell;
      }
    }
    return best;
  }();
  return farthest;
}

void BM_CostmapCampus(benchmark::State& state) {
  const OccupancyGrid& grid = Campus().map.grid;
  for (auto _ : state) {
    Costmap costmap(grid, CostmapOptions{});
    benchmark::DoNotOptimize(costmap.costs().data());
  }
  state.counters["cells"] = static_cast<double>(grid.cells().size());
}
BENCHMARK(BM_CostmapCampus)->Unit(benchmark::kMillisecond);

// A 1200 x 800-cell map (60 m x 40 m) of rooms: walls every 100 cells with
// doors, the east third unknown; and the same with one 40 x 40-cell local
// change (an L of new wall, a few obstacle cells, unknown revealed as free),
// the size of what one SLAM update or a set of scan marks changes.
OccupancyGrid Rooms(bool changed) {
  OccupancyGrid grid(1200, 800, 0.05, {-10.0, -5.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 800; ++row) {
    for (int col = 0; col < 1200; ++col) {
      const bool wall = (col % 100 < 3 && (row % 100 < 40 || row % 100 > 60)) ||
                        (row % 100 < 3 && (col % 100 < 40 || col % 100 > 60)) || col >= 1197 ||
                        row >= 797;
      if (wall) {
        grid.at({col, row}) = OccupancyGrid::kOccupied;
      } else if (col >= 800) {
        grid.at({col, row}) = OccupancyGrid::kUnknown;
      }
    }
  }
  if (changed) {
    const CellIndex corner{780, 420};  // straddles the unknown edge
    for (int i = 0; i < 40; ++i) {
      for (int j = 0; j < 40; ++j) {
        int8_t& value = grid.at({corner.col + i, corner.row + j});
        if (value < 0) value = OccupancyGrid::kFree;
      }
      grid.at({corner.col + i, corner.row + 25}) = OccupancyGrid::kOccupied;
      grid.at({corner.col + 30, corner.row + i}) = OccupancyGrid::kOccupied;
      grid.at({corner.col + (i * 7) % 40, corner.row + (i * 13) % 40}) = OccupancyGrid::kOccupied;
    }
  }
  return grid;
}

// The full rebuild (the layers reused), what every new map cost before Update.
void BM_CostmapRebuildRooms(benchmark::State& state) {
  const OccupancyGrid grid = Rooms(false);
  Costmap costmap(grid, CostmapOptions{});
  for (auto _ : state) {
    costmap.Rebuild(grid, CostmapOptions{});
    benchmark::DoNotOptimize(costmap.costs().data());
  }
  state.counters["cells"] = static_cast<double>(grid.cells().size());
}
BENCHMARK(BM_CostmapRebuildRooms)->Unit(benchmark::kMillisecond);

// Update with the 40 x 40 change, alternately applied and undone: every
// iteration is one incremental update of the same size.
void BM_CostmapUpdateRoomsLocalChange(benchmark::State& state) {
  const OccupancyGrid grids[2] = {Rooms(false), Rooms(true)};
  Costmap costmap(grids[0], CostmapOptions{});
  int next = 1;
  int64_t incremental = 0;
  for (auto _ : state) {
    const Costmap::UpdateKind kind = costmap.Update(grids[next], CostmapOptions{});
    incremental += kind == Costmap::UpdateKind::kIncremental;
    next ^= 1;
    benchmark::DoNotOptimize(costmap.costs().data());
  }
  state.counters["incremental"] =
      benchmark::Counter(static_cast<double>(incremental), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_CostmapUpdateRoomsLocalChange)->Unit(benchmark::kMillisecond);

// Update with an unchanged map: the cost of finding that nothing changed.
void BM_CostmapUpdateRoomsUnchanged(benchmark::State& state) {
  const OccupancyGrid grid = Rooms(false);
  Costmap costmap(grid, CostmapOptions{});
  for (auto _ : state) {
    benchmark::DoNotOptimize(costmap.Update(grid, CostmapOptions{}));
  }
}
BENCHMARK(BM_CostmapUpdateRoomsUnchanged)->Unit(benchmark::kMillisecond);

// One-to-all from the start pose, a fresh tree each time (allocates ~17 MB).
void BM_SearchAllCampus(benchmark::State& state) {
  const Costmap& costmap = CampusCostmap();
  const GlobalPlanner planner;
  std::size_t settled = 0;
  for (auto _ : state) {
    ShortestPathTree tree = planner.Search(costmap, StartCell());
    settled = tree.settled_count();
    benchmark::DoNotOptimize(settled);
  }
  state.counters["settled"] = static_cast<double>(settled);
}
BENCHMARK(BM_SearchAllCampus)->Unit(benchmark::kMillisecond);

// The same into a reused tree (what a caller searching every decision can do).
void BM_SearchAllCampusReuse(benchmark::State& state) {
  const Costmap& costmap = CampusCostmap();
  const GlobalPlanner planner;
  ShortestPathTree tree;
  for (auto _ : state) {
    planner.Search(costmap, StartCell(), {}, &tree);
    benchmark::DoNotOptimize(tree.settled_count());
  }
  state.counters["settled"] = static_cast<double>(tree.settled_count());
}
BENCHMARK(BM_SearchAllCampusReuse)->Unit(benchmark::kMillisecond);

// A single-goal plan to the farthest reachable cell (early stop barely helps there).
void BM_PlanAcrossCampus(benchmark::State& state) {
  const Costmap& costmap = CampusCostmap();
  const GlobalPlanner planner;
  const Point2d start_m{Campus().start.x_m, Campus().start.y_m};
  const Point2d goal_m = costmap.CellCenter(FarthestCell());
  double length_m = 0.0;
  for (auto _ : state) {
    const auto path = planner.Plan(costmap, start_m, goal_m);
    if (!path) {
      state.SkipWithError("no path across campus");
      return;
    }
    length_m = path->length_m;
  }
  state.counters["path_m"] = length_m;
}
BENCHMARK(BM_PlanAcrossCampus)->Unit(benchmark::kMillisecond);

// The reachable cell whose path from the start is nearest `length_m` long.
CellIndex CellAtPathLength(double length_m) {
  const Costmap& costmap = CampusCostmap();
  static const ShortestPathTree all = GlobalPlanner().Search(costmap, StartCell());
  CellIndex goal = StartCell();
  for (int row = 0; row < costmap.height_cells(); ++row) {
    for (int col = 0; col < costmap.width_cells(); ++col) {
      const CellIndex cell{col, row};
      if (all.Reachable(cell) &&
          std::abs(all.PathLengthM(cell) - length_m) < std::abs(all.PathLengthM(goal) - length_m)) {
        goal = cell;
      }
    }
  }
  return goal;
}

// Single-goal plans from the start to cells 10, 30 and 60 m away along the path (the
// navigator's goals), into a reused tree as the navigator does; second argument 1: on a
// goal-distance field, as the navigator plans (the field made once, outside the loop).
void BM_PlanCampusReuse(benchmark::State& state) {
  const Costmap& costmap = CampusCostmap();
  const GlobalPlanner planner;
  const CellIndex goal = CellAtPathLength(static_cast<double>(state.range(0)));
  ShortestPathTree field;
  if (state.range(1) != 0) planner.DistancesToGoal(costmap, goal, StartCell(), &field);
  const Point2d start_m{Campus().start.x_m, Campus().start.y_m};
  ShortestPathTree tree;
  for (auto _ : state) {
    const auto path = planner.Plan(costmap, start_m, costmap.CellCenter(goal), &tree,
                                   state.range(1) != 0 ? &field : nullptr);
    if (!path) {
      state.SkipWithError("no path");
      return;
    }
    benchmark::DoNotOptimize(path->length_m);
  }
  state.counters["settled"] = static_cast<double>(tree.settled_count());
}
BENCHMARK(BM_PlanCampusReuse)->ArgsProduct({{10, 30, 60}, {0, 1}})->Unit(benchmark::kMillisecond);

// The goal-distance field for a goal 10, 30 or 60 m from the robot (once per goal).
void BM_DistancesToGoalCampus(benchmark::State& state) {
  const Costmap& costmap = CampusCostmap();
  const GlobalPlanner planner;
  const CellIndex goal = CellAtPathLength(static_cast<double>(state.range(0)));
  ShortestPathTree field;
  for (auto _ : state) {
    planner.DistancesToGoal(costmap, goal, StartCell(), &field);
    benchmark::DoNotOptimize(field.settled_count());
  }
  state.counters["settled"] = static_cast<double>(field.settled_count());
}
BENCHMARK(BM_DistancesToGoalCampus)->Arg(10)->Arg(30)->Arg(60)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
