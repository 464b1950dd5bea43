// Simulator speed: one 720-beam scan in a large world, and simulated seconds
// per wall second of a bare Simulator::Step loop (no LCM) and of the SimNode
// publishing on memq:// with no other node.
//
//   build/drivers/sim/sim_benchmark [--benchmark_filter=...]
//
// Uses worlds/campus/map.yaml; SIM_BENCHMARK_WORLD=<map.yaml> chooses another.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/inproc_host.h"
#include "common/map_io.h"
#include "drivers/sim/lidar.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/sim_node.h"
#include "drivers/sim/sim_world.h"
#include "drivers/sim/simulator.h"

namespace aslam {
namespace {

struct BenchWorld {
  std::string name;
  std::unique_ptr<SimWorld> world;
  std::vector<Pose2d> poses;  // free poses with room for the robot
};

const BenchWorld& GetWorld() {
  static const BenchWorld* const bench = [] {
    auto* result = new BenchWorld;
    const char* const chosen = std::getenv("SIM_BENCHMARK_WORLD");
    const std::string map_yaml = chosen ? chosen : ASLAM_SOURCE_DIR "/worlds/campus/map.yaml";
    const OccupancyGrid grid = LoadMap(map_yaml).grid;
    result->name = std::filesystem::path(map_yaml).parent_path().filename().string();
    result->world = std::make_unique<SimWorld>(grid);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> ux(grid.origin_m().x_m,
                                              grid.origin_m().x_m + grid.width_m());
    std::uniform_real_distribution<double> uy(grid.origin_m().y_m,
                                              grid.origin_m().y_m + grid.height_m());
    std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
    while (result->poses.size() < 64) {
      const Pose2d pose{ux(rng), uy(rng), yaw(rng)};
      if (!result->world->CircleCollides({pose.x_m, pose.y_m}, 0.3)) result->poses.push_back(pose);
    }
    std::fprintf(stderr, "sim_benchmark world: %s, %d x %d cells, free %.0f m^2\n",
                 result->name.c_str(), grid.width_cells(), grid.height_cells(),
                 result->world->free_area_m2());
    return result;
  }();
  return *bench;
}

void BM_LidarScan(benchmark::State& state) {
  const BenchWorld& bench = GetWorld();
  const LidarModel lidar{LidarOptions{}};
  std::mt19937_64 rng(1);
  std::size_t i = 0;
  int64_t returns = 0, beams = 0;
  for (auto _ : state) {
    const LidarScan scan =
        lidar.Scan(*bench.world, bench.poses[i++ % bench.poses.size()], 0, 0, rng);
    benchmark::DoNotOptimize(scan.range_m.data());
    for (float r : scan.range_m) returns += r > 0.0f;
    beams += scan.range_m.size();
  }
  state.SetLabel(bench.name);
  state.counters["returns_fraction"] = static_cast<double>(returns) / std::max<int64_t>(beams, 1);
}
BENCHMARK(BM_LidarScan)->Unit(benchmark::kMicrosecond);

// The same beams without noise, with and without the distance-field skipping.
template <bool kPlain>
void BM_ExactRanges(benchmark::State& state) {
  const BenchWorld& bench = GetWorld();
  const LidarModel lidar{LidarOptions{}};
  std::size_t i = 0;
  for (auto _ : state) {
    const Pose2d& pose = bench.poses[i++ % bench.poses.size()];
    if constexpr (kPlain) {
      for (int beam = 0; beam < lidar.num_beams(); ++beam) {
        benchmark::DoNotOptimize(bench.world->CastRayPlain({pose.x_m, pose.y_m},
                                                           pose.yaw_rad + lidar.BeamAngle(beam),
                                                           lidar.options().range_max_m));
      }
    } else {
      benchmark::DoNotOptimize(lidar.ExactRanges(*bench.world, pose).data());
    }
  }
  state.SetLabel(bench.name);
}
BENCHMARK_TEMPLATE(BM_ExactRanges, false)
    ->Name("BM_ExactRanges/distance_field")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_ExactRanges, true)
    ->Name("BM_ExactRanges/plain_dda")
    ->Unit(benchmark::kMicrosecond);

// One iteration = one simulated second (100 physics steps, 10 scans, 50
// odometry and truth samples, 1 status). A bump-and-turn driver keeps the
// robot moving through the world: forward until something is close ahead,
// then turn in place.
void BM_SimulatorSecond(benchmark::State& state) {
  const BenchWorld& bench = GetWorld();
  const SimulatorOptions options;
  Simulator sim(bench.world->map(), bench.poses[0], options);
  bool turning = false;
  int64_t sim_steps = 0;
  double driven_m = 0.0;
  Pose2d last_truth = sim.true_pose();
  for (auto _ : state) {
    for (int step = 0; step < 100; ++step) {
      sim.SetCommand({sim.utime(), turning ? 0.0 : 0.5, turning ? 1.5 : 0.1});
      const SimStepOutput out = sim.Step();
      if (out.scan) {
        const std::vector<float>& ranges = out.scan->range_m;
        float ahead = 100.0f;
        for (int beam = 300; beam <= 420; ++beam) {  // +-30 deg around the heading
          if (ranges[beam] > 0.0f) ahead = std::min(ahead, ranges[beam]);
        }
        turning = ahead < (turning ? 1.5f : 0.8f) || sim.in_collision();
      }
      if (out.truth) {
        driven_m +=
            std::hypot(out.truth->pose.x_m - last_truth.x_m, out.truth->pose.y_m - last_truth.y_m);
        last_truth = out.truth->pose;
      }
      benchmark::DoNotOptimize(out);
    }
    sim_steps += 100;
  }
  const double sim_seconds = sim_steps / options.physics_rate_hz;
  state.counters["realtime_factor"] = benchmark::Counter(sim_seconds, benchmark::Counter::kIsRate);
  state.counters["collisions"] = static_cast<double>(sim.collisions());
  state.counters["driven_m_per_sim_s"] = driven_m / std::max(sim_seconds, 1e-9);
  state.SetLabel(bench.name);
}
BENCHMARK(BM_SimulatorSecond)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The in-process hosting: SimNode encodes and publishes every message on
// memq:// and the host dispatches them, with no other node listening. The
// robot follows a repeating drive of arcs and turns from a free start.
void BM_SimNodeSecondInProcess(benchmark::State& state) {
  const BenchWorld& bench = GetWorld();
  InProcessHost host;
  const SimulatorOptions options;
  Simulator sim(bench.world->map(), bench.poses[0], options);
  SimNode node(host.lcm(), sim,
               {bench.name, ScriptedDrive({{4.0, 0.4, 0.2}, {2.0, 0.0, 1.0}}, /*repeat=*/true)});
  int64_t sim_steps = 0;
  for (auto _ : state) {
    for (int step = 0; step < 100; ++step) {
      node.Tick();
      host.DispatchPending();
    }
    sim_steps += 100;
  }
  const double sim_seconds = sim_steps / options.physics_rate_hz;
  state.counters["realtime_factor"] = benchmark::Counter(sim_seconds, benchmark::Counter::kIsRate);
  state.SetLabel(bench.name);
}
BENCHMARK(BM_SimNodeSecondInProcess)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_SimWorldConstruction(benchmark::State& state) {
  const BenchWorld& bench = GetWorld();
  for (auto _ : state) {
    SimWorld world(bench.world->map());
    benchmark::DoNotOptimize(world.free_area_m2());
  }
  state.SetLabel(bench.name);
}
BENCHMARK(BM_SimWorldConstruction)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
