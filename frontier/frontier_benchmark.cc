// Frontier extraction on the campus world (0.05 m/cell) with its east half
// unknown: the whole extraction, and the reachability step alone.
//
//   build/frontier/frontier_benchmark

#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <string>

#include "common/world_file.h"
#include "frontier/frontier_extractor.h"

namespace aslam {
namespace {

const WorldInfo& Campus() {
  static const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus");
  return world;
}

// The campus map with every cell east of its middle column unknown.
const OccupancyGrid& HalfExploredCampus() {
  static const OccupancyGrid grid = [] {
    OccupancyGrid g = Campus().map.grid;
    for (int row = 0; row < g.height_cells(); ++row) {
      for (int col = g.width_cells() / 2; col < g.width_cells(); ++col) {
        g.at({col, row}) = OccupancyGrid::kUnknown;
      }
    }
    return g;
  }();
  return grid;
}

// One thread, as in a run (RunExploreInProcess pins OpenCV to the caller's thread).
const bool kSingleThreaded = (cv::setNumThreads(0), true);

Point2d Start() { return {Campus().start.x_m, Campus().start.y_m}; }

// Argument: frontier.target_clearance_m in cm (0: targets without room to stand, no distance
// transform).
void BM_FindFrontiersCampus(benchmark::State& state) {
  const OccupancyGrid& grid = HalfExploredCampus();
  FrontierOptions options;
  options.target_clearance_m = static_cast<double>(state.range(0)) / 100.0;
  FrontierScratch scratch;
  FrontierExtractionStats stats;
  for (auto _ : state) {
    const std::vector<Frontier> frontiers = FindFrontiers(grid, Start(), options, &stats, &scratch);
    benchmark::DoNotOptimize(frontiers.data());
  }
  state.counters["cells"] = static_cast<double>(grid.cells().size());
  state.counters["frontier_cells"] = stats.frontier_cells;
  state.counters["segments"] = stats.segments;
}
BENCHMARK(BM_FindFrontiersCampus)->Arg(0)->Arg(15)->Unit(benchmark::kMillisecond);

void BM_ReachableCellsCampus(benchmark::State& state) {
  const OccupancyGrid& grid = HalfExploredCampus();
  const FrontierOptions options;
  const Costmap costmap(grid, options.costmap);
  const CellIndex start = grid.WorldToCell(Start());
  ReachableCells reachable;
  for (auto _ : state) {
    reachable.Compute(costmap, start, options.global_planner);
    benchmark::DoNotOptimize(reachable.Reachable(start));
  }
}
BENCHMARK(BM_ReachableCellsCampus)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
