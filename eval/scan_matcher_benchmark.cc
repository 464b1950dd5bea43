// Correlative scan matching on simulated lidar scans in worlds/office: a
// keyframe match (default window), a loop-closure match (wide window) and the
// construction of a 10-keyframe local map. Arg: point spacing in cm.

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/world_file.h"
#include "drivers/sim/lidar.h"
#include "drivers/sim/sim_world.h"
#include "slam/scan_matcher.h"

namespace aslam {
namespace {

constexpr int kKeyframes = 10;

// Ten keyframes 0.3 m apart along the start's longest free view, a query scan
// just past them and one back near the first keyframe (a loop closure).
struct Scene {
  std::vector<Pose2d> keyframe_poses;
  std::vector<LidarScan> keyframe_scans;
  Pose2d query_truth;
  LidarScan query_scan;
  Pose2d loop_truth;
  LidarScan loop_scan;
};

const Scene& OfficeScene() {
  static const Scene scene = [] {
    const WorldInfo info = LoadWorld(ASLAM_SOURCE_DIR "/worlds/office");
    const SimWorld world(info.map.grid);
    const LidarModel lidar{LidarOptions{}};
    std::mt19937_64 rng(1);
    Scene s;
    for (int k = 0; k < kKeyframes; ++k) {
      s.keyframe_poses.push_back(info.start *
                                 Pose2d{0.3 * k, 0.05 * std::sin(k), 0.05 * std::cos(k)});
      s.keyframe_scans.push_back(lidar.Scan(world, s.keyframe_poses.back(), 0, k, rng));
    }
    s.query_truth = info.start * Pose2d{0.3 * kKeyframes - 0.1, 0.04, 0.08};
    s.query_scan = lidar.Scan(world, s.query_truth, 0, kKeyframes, rng);
    s.loop_truth = info.start * Pose2d{0.4, -0.1, -0.2};
    s.loop_scan = lidar.Scan(world, s.loop_truth, 0, kKeyframes + 1, rng);
    return s;
  }();
  return scene;
}

std::vector<PosedPoints> Keyframes(int first, int count, double spacing_m) {
  const Scene& scene = OfficeScene();
  std::vector<PosedPoints> scans;
  for (int k = first; k < first + count; ++k) {
    scans.push_back({scene.keyframe_poses[k], std::make_shared<const PointCloud2d>(ScanToPoints(
                                                  scene.keyframe_scans[k], spacing_m))});
  }
  return scans;
}

void BM_BuildCorrelationMap(benchmark::State& state) {
  const std::vector<PosedPoints> scans = Keyframes(0, kKeyframes, state.range(0) / 100.0);
  const ScanMatcherOptions options;
  for (auto _ : state) {
    CorrelationMap map(scans, options);
    benchmark::DoNotOptimize(map);
  }
}
BENCHMARK(BM_BuildCorrelationMap)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond);

void Match(benchmark::State& state, const CorrelationMap& map, const LidarScan& scan,
           const Pose2d& truth, const Pose2d& prediction, const SearchWindow& window) {
  const ScanMatcher matcher{ScanMatcherOptions{}};
  const PointCloud2d points = ScanToPoints(scan, state.range(0) / 100.0);
  ScanMatchResult result;
  for (auto _ : state) {
    result = matcher.Match(map, points, prediction, window);
    benchmark::DoNotOptimize(result);
  }
  state.counters["points"] = points.size();
  state.counters["response"] = result.response;
  state.counters["error_m"] = std::hypot(result.pose.x_m - truth.x_m, result.pose.y_m - truth.y_m);
  state.counters["error_rad"] = std::abs(WrapAngle(result.pose.yaw_rad - truth.yaw_rad));
  state.counters["refined_error_m"] =
      std::hypot(result.refined_pose.x_m - truth.x_m, result.refined_pose.y_m - truth.y_m);
  state.counters["scored"] = result.candidates_scored;
  state.counters["sigma_x_m"] = std::sqrt(result.covariance(0, 0));
  state.counters["sigma_y_m"] = std::sqrt(result.covariance(1, 1));
}

void BM_KeyframeMatch(benchmark::State& state) {
  const Scene& scene = OfficeScene();
  const CorrelationMap map(Keyframes(0, kKeyframes, state.range(0) / 100.0), ScanMatcherOptions{});
  // Odometry error of a few cm and degrees over one keyframe step.
  const Pose2d prediction = scene.query_truth * Pose2d{0.07, -0.05, 0.06};
  Match(state, map, scene.query_scan, scene.query_truth, prediction, SearchWindow{0.3, 0.35});
}
BENCHMARK(BM_KeyframeMatch)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond);

void BM_LoopClosureMatch(benchmark::State& state) {
  const Scene& scene = OfficeScene();
  // The candidate keyframe and its neighbours.
  const CorrelationMap map(Keyframes(0, 3, state.range(0) / 100.0), ScanMatcherOptions{});
  // Drift accumulated around a loop.
  const Pose2d prediction = scene.loop_truth * Pose2d{0.9, -1.1, 0.3};
  Match(state, map, scene.loop_scan, scene.loop_truth, prediction, SearchWindow{2.0, 0.5});
}
BENCHMARK(BM_LoopClosureMatch)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
