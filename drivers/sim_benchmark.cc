// Simulator speed: one 720-beam scan in a large world, and simulated seconds
// per wall second of a bare Simulator::Step loop (no LCM, no other node).
//
//   build-sim/drivers/sim_benchmark [--benchmark_filter=...]
//
// Uses worlds/campus/map.yaml when it exists and loads, else a synthetic
// 70 m x 60 m office (1400 x 1200 cells) of rooms, corridors and a hall;
// SIM_BENCHMARK_WORLD=<map.yaml> or =synthetic chooses.

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

#include "common/map_io.h"
#include "drivers/lidar.h"
#include "drivers/sim_world.h"
#include "drivers/simulator.h"

namespace aslam {
namespace {

constexpr double kResolutionM = 0.05;

class OfficeBuilder {
 public:
  OfficeBuilder() : grid_(1400, 1200, kResolutionM, {0.0, 0.0}, OccupancyGrid::kFree) {}

  // Sets every cell whose centre lies in [x0, x1] x [y0, y1] (metres).
  void Fill(double x0, double y0, double x1, double y1, int8_t value) {
    const int c0 = std::max(0, static_cast<int>(std::ceil(x0 / kResolutionM - 0.5)));
    const int c1 =
        std::min(grid_.width_cells() - 1, static_cast<int>(std::floor(x1 / kResolutionM - 0.5)));
    const int r0 = std::max(0, static_cast<int>(std::ceil(y0 / kResolutionM - 0.5)));
    const int r1 =
        std::min(grid_.height_cells() - 1, static_cast<int>(std::floor(y1 / kResolutionM - 0.5)));
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) grid_.at({c, r}) = value;
    }
  }
  void Wall(double x0, double y0, double x1, double y1) { Fill(x0, y0, x1, y1, 100); }
  void Clear(double x0, double y0, double x1, double y1) { Fill(x0, y0, x1, y1, 0); }

  OccupancyGrid Build() {
    constexpr double kWall = 0.15, kDoor = 1.0;
    const double width = grid_.width_m(), height = grid_.height_m();
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> unit(0.0, 1.0);

    // Three horizontal corridors (2.4 m) at y = 10, 30, 50; rooms 6 m wide
    // between them, back to back along y = 20 and y = 40.
    for (double corridor_y : {10.0, 30.0, 50.0}) {
      for (double side : {-1.2, 1.2}) {
        const double y = corridor_y + side;
        Wall(0.0, y - kWall / 2, width, y + kWall / 2);
      }
    }
    for (double y : {20.0, 40.0}) Wall(0.0, y - kWall / 2, width, y + kWall / 2);
    for (double x = 6.0; x < width; x += 6.0) Wall(x - kWall / 2, 0.0, x + kWall / 2, height);
    // Corridors run through the partitions; a vertical corridor links them.
    for (double corridor_y : {10.0, 30.0, 50.0})
      Clear(0.0, corridor_y - 1.1, width, corridor_y + 1.1);
    Clear(33.8, 0.0, 36.2, height);
    // Doors from every room to its corridor.
    for (double x = 0.0; x < width; x += 6.0) {
      const double door_x = x + 1.0 + 3.5 * unit(rng);
      for (double corridor_y : {10.0, 30.0, 50.0}) {
        for (double side : {-1.2, 1.2}) {
          const double y = corridor_y + side;
          Clear(door_x, y - kWall, door_x + kDoor, y + kWall);
        }
      }
    }
    // Desks and cabinets in the rooms.
    for (int i = 0; i < 600; ++i) {
      const double x = width * unit(rng), y = height * unit(rng);
      const bool desk = unit(rng) < 0.7;
      const double w = desk ? 1.6 : 0.5, h = desk ? 0.8 : 1.2;
      if (std::abs(y - 10.0) < 2.0 || std::abs(y - 30.0) < 2.0 || std::abs(y - 50.0) < 2.0) {
        continue;
      }
      if (x > 33.0 && x < 37.0) continue;
      Wall(x, y, x + w, y + h);
    }
    // An open hall with pillars: long beams.
    Clear(44.0, 21.3, 68.0, 38.7);
    for (double x = 47.0; x < 68.0; x += 5.0) {
      for (double y = 25.0; y < 38.0; y += 5.0) Wall(x - 0.2, y - 0.2, x + 0.2, y + 0.2);
    }
    // Outer walls.
    Wall(0.0, 0.0, width, kWall);
    Wall(0.0, height - kWall, width, height);
    Wall(0.0, 0.0, kWall, height);
    Wall(width - kWall, 0.0, width, height);
    return grid_;
  }

 private:
  OccupancyGrid grid_;
};

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
    OccupancyGrid grid;
    if (map_yaml != "synthetic" && std::filesystem::exists(map_yaml)) {
      try {
        grid = LoadMap(map_yaml).grid;
        result->name = std::filesystem::path(map_yaml).parent_path().filename().string();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "sim_benchmark: %s; using the synthetic office\n", e.what());
      }
    }
    if (grid.empty()) {
      grid = OfficeBuilder().Build();
      result->name = "synthetic office";
    }
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
        driven_m += std::hypot(out.truth->pose.x_m - last_truth.x_m,
                               out.truth->pose.y_m - last_truth.y_m);
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
