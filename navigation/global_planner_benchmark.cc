// Costmap construction and Dijkstra on the campus world (0.05 m/cell).
//
//   build-gp/navigation/global_planner_benchmark

#include <benchmark/benchmark.h>

#include <string>

#include "navigation/costmap.h"
#include "navigation/global_planner.h"
#include "worlds/worldgen.h"

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

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
