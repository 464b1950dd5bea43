// One DWA control cycle in worlds/office: the robot at the world's start
// pose (a corridor crossing, facing the longest free view), a path along that
// corridor, a 720-ray scan ray-cast from the true map.
//
//   build-dwa/navigation/dwa_benchmark

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/world_file.h"
#include "navigation/dwa_planner.h"
#include "navigation/local_obstacles.h"

namespace aslam {
namespace {

bool Solid(const OccupancyGrid& grid, const Point2d& p) {
  return grid.ValueOr(grid.WorldToCell(p), OccupancyGrid::kUnknown) >= 65;
}

struct Scene {
  OccupancyGrid map;
  Pose2d robot;
  std::vector<Point2d> scan_m;  // end points in "map"
  std::vector<Point2d> path_m;
};

const Scene& OfficeScene() {
  static const Scene scene = [] {
    Scene s;
    const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/office");
    s.map = world.map.grid;
    s.robot = world.start;
    const double step_m = 0.5 * s.map.resolution_m();
    // 720 rays, 10 m range, marched at half a cell.
    for (int i = 0; i < 720; ++i) {
      const double angle = s.robot.yaw_rad - M_PI + 2.0 * M_PI * i / 720;
      for (double r = step_m; r <= 10.0; r += step_m) {
        const Point2d p{s.robot.x_m + r * std::cos(angle), s.robot.y_m + r * std::sin(angle)};
        if (Solid(s.map, p)) {
          s.scan_m.push_back(p);
          break;
        }
      }
    }
    // The path: straight along the corridor ahead, 5 cm apart, stopping 0.6 m short of a wall.
    const double c = std::cos(s.robot.yaw_rad), sn = std::sin(s.robot.yaw_rad);
    for (double d = 0.0; d <= 12.0; d += 0.05) {
      const Point2d p{s.robot.x_m + d * c, s.robot.y_m + d * sn};
      if (Solid(s.map, {p.x_m + 0.6 * c, p.y_m + 0.6 * sn})) break;
      s.path_m.push_back(p);
    }
    return s;
  }();
  return scene;
}

void BM_LocalObstaclesBuild(benchmark::State& state) {
  const Scene& s = OfficeScene();
  const LocalObstaclesOptions options;
  for (auto _ : state) {
    LocalObstacles obstacles(s.map, s.scan_m, s.robot, options);
    benchmark::DoNotOptimize(obstacles);
  }
  state.counters["scan_points"] = static_cast<double>(s.scan_m.size());
}
BENCHMARK(BM_LocalObstaclesBuild)->Unit(benchmark::kMicrosecond);

// Plan only (the obstacle layer built once), from rest and at cruising speed.
void BM_DwaPlan(benchmark::State& state) {
  const Scene& s = OfficeScene();
  const DwaPlanner planner{DwaOptions()};
  const LocalObstacles obstacles(s.map, s.scan_m, s.robot, LocalObstaclesOptions());
  const DwaVelocity current{state.range(0) / 100.0, 0.0};
  DwaResult result;
  for (auto _ : state) {
    result = planner.Plan(s.robot, current, s.path_m, obstacles);
    benchmark::DoNotOptimize(result);
  }
  state.counters["found"] = result.found;
  state.counters["evaluated"] = result.trajectories_evaluated;
  state.counters["colliding"] = result.trajectories_colliding;
  state.counters["v_mps"] = result.command.linear_mps;
  state.counters["path_m"] = 0.05 * (s.path_m.size() - 1);
}
BENCHMARK(BM_DwaPlan)->Arg(0)->Arg(40)->Unit(benchmark::kMicrosecond);

// The whole control cycle: rebuild the obstacle layer, then plan.
void BM_DwaCycle(benchmark::State& state) {
  const Scene& s = OfficeScene();
  const DwaPlanner planner{DwaOptions()};
  const LocalObstaclesOptions options;
  for (auto _ : state) {
    const LocalObstacles obstacles(s.map, s.scan_m, s.robot, options);
    DwaResult result = planner.Plan(s.robot, {0.4, 0.0}, s.path_m, obstacles);
    benchmark::DoNotOptimize(result);
  }
}
BENCHMARK(BM_DwaCycle)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
