// One U1 decision (docs/architecture.md §5): 100 frontiers on a 5000-node SLAM-shaped pose
// graph, log det of the reduced Laplacian the incremental way, from scratch
// with CHOLMOD, and dense (Eigen, one candidate), side by side.
//
//   build/utility/spanning_trees_benchmark

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "utility/benchmark_scene.h"
#include "utility/hallucination.h"
#include "utility/spanning_trees.h"

namespace aslam {
namespace {

constexpr int kNumNodes = 5000;
constexpr int kNumFrontiers = 100;
constexpr double kResolution_m = 0.05;
constexpr double kArena_m = 40.0;

// The scene: a 5000-keyframe random exploration walk (0.5 m steps, smooth
// heading) in a 40 m square, odometry edges along it and loop closures for ~10 %
// of the keyframes to the nearest keyframe >= 20 older within 1.5 m; a map that
// is free along the walk with scattered obstacles and unknown elsewhere; 100
// frontiers with straight planned paths of 2..400 cells from the robot.
struct Scene {
  PoseGraph graph;
  OccupancyGrid map;
  std::vector<std::vector<Point2d>> paths_m;
  WeightedGraph weighted;
  std::vector<GraphExtension> extensions;
  int num_closures = 0;
};

const Scene& GetScene() {
  static const Scene scene = [] {
    Scene s;
    std::mt19937 rng(42);
    std::normal_distribution<double> turn(0.0, 0.3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double x = kArena_m / 2, y = kArena_m / 2, yaw = 0.0;
    for (int i = 0; i < kNumNodes; ++i) {
      PoseGraphNode node;
      node.id = i;
      node.pose = {x, y, yaw};
      s.graph.nodes.push_back(node);
      yaw += turn(rng);
      double nx = x + 0.5 * std::cos(yaw), ny = y + 0.5 * std::sin(yaw);
      if (nx < 1 || ny < 1 || nx > kArena_m - 1 || ny > kArena_m - 1) {  // bounce off the walls
        yaw += M_PI;
        nx = x + 0.5 * std::cos(yaw);
        ny = y + 0.5 * std::sin(yaw);
      }
      x = nx;
      y = ny;
    }
    for (int i = 1; i < kNumNodes; ++i) {
      PoseGraphEdge edge;
      edge.from_id = i - 1;
      edge.to_id = i;
      edge.measurement = s.graph.nodes[i - 1].pose.Between(s.graph.nodes[i].pose);
      edge.information = SyntheticEdgeInformation(0.02 + 0.03 * unit(rng), 0.005 + 0.01 * unit(rng),
                                                  unit(rng) * M_PI);
      s.graph.edges.push_back(edge);
    }
    for (int i = 21; i < kNumNodes; ++i) {
      if (unit(rng) > 0.1) continue;
      int best = -1;
      double best_sq = 1.5 * 1.5;
      for (int j = 0; j < i - 20; ++j) {
        const double dx = s.graph.nodes[j].pose.x_m - s.graph.nodes[i].pose.x_m;
        const double dy = s.graph.nodes[j].pose.y_m - s.graph.nodes[i].pose.y_m;
        if (dx * dx + dy * dy < best_sq) best_sq = dx * dx + dy * dy, best = j;
      }
      if (best < 0) continue;
      PoseGraphEdge edge;
      edge.from_id = best;
      edge.to_id = i;
      edge.kind = EdgeKind::kLoopClosure;
      edge.measurement = s.graph.nodes[best].pose.Between(s.graph.nodes[i].pose);
      edge.information = SyntheticEdgeInformation(0.05 + 0.05 * unit(rng), 0.01 + 0.02 * unit(rng),
                                                  unit(rng) * M_PI);
      s.graph.edges.push_back(edge);
      ++s.num_closures;
    }

    const int cells = static_cast<int>(kArena_m / kResolution_m);
    s.map = OccupancyGrid(cells, cells, kResolution_m, {0.0, 0.0}, OccupancyGrid::kUnknown);
    for (const PoseGraphNode& node : s.graph.nodes) {  // the robot saw ~1.5 m around itself
      const CellIndex c = s.map.WorldToCell({node.pose.x_m, node.pose.y_m});
      for (int dr = -30; dr <= 30; ++dr) {
        for (int dc = -30; dc <= 30; ++dc) {
          const CellIndex cell{c.col + dc, c.row + dr};
          if (s.map.Contains(cell) && dr * dr + dc * dc <= 900)
            s.map.at(cell) = OccupancyGrid::kFree;
        }
      }
    }
    for (int8_t& value : s.map.mutable_cells()) {
      if (value == OccupancyGrid::kFree && unit(rng) < 0.05) value = OccupancyGrid::kOccupied;
    }

    const Pose2d robot = s.graph.nodes.back().pose;
    std::uniform_int_distribution<int> length(2, 400);
    for (int f = 0; f < kNumFrontiers; ++f) {
      const double angle = unit(rng) * 2 * M_PI;
      const int num_cells = length(rng);
      std::vector<Point2d> path;
      for (int c = 0; c < num_cells; ++c) {
        const double px =
            std::clamp(robot.x_m + c * kResolution_m * std::cos(angle), 0.0, kArena_m - 1e-6);
        const double py =
            std::clamp(robot.y_m + c * kResolution_m * std::sin(angle), 0.0, kArena_m - 1e-6);
        path.push_back(s.map.CellCenter(s.map.WorldToCell({px, py})));
      }
      s.paths_m.push_back(path);
    }
    s.weighted = ToWeightedGraph(s.graph);
    for (const auto& path : s.paths_m)
      s.extensions.push_back(HallucinatePath(s.graph, path, s.map, {}));

    // Sanity: incremental equals from scratch on every candidate.
    AbortUnlessIncrementalMatchesSparse(s.weighted, s.extensions, "random walk");
    return s;
  }();
  return scene;
}

void SceneCounters(benchmark::State& state, const Scene& scene) {
  int new_nodes = 0, edges = 0;
  for (const GraphExtension& e : scene.extensions) {
    new_nodes += e.num_new_nodes;
    edges += static_cast<int>(e.edges.size());
  }
  state.counters["nodes"] = kNumNodes;
  state.counters["closures"] = scene.num_closures;
  state.counters["new_nodes/frontier"] = static_cast<double>(new_nodes) / kNumFrontiers;
  state.counters["new_edges/frontier"] = static_cast<double>(edges) / kNumFrontiers;
}

// One decision's log dets, the incremental way: one factorization + 100 Schur complements.
void BM_DecisionLogDet_Incremental(benchmark::State& state) {
  const Scene& scene = GetScene();
  int cached = 0;
  for (auto _ : state) {
    IncrementalLogDet incremental(scene.weighted);
    for (const GraphExtension& extension : scene.extensions) {
      benchmark::DoNotOptimize(incremental.LogDet(extension));
    }
    cached = incremental.cached_solves();
  }
  SceneCounters(state, scene);
  state.counters["cached_solves"] = cached;
}
BENCHMARK(BM_DecisionLogDet_Incremental)->Unit(benchmark::kMillisecond);

// Parts of the above: D-opt weights of the pose graph, and the one factorization.
void BM_ToWeightedGraph(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) benchmark::DoNotOptimize(ToWeightedGraph(scene.graph));
}
BENCHMARK(BM_ToWeightedGraph)->Unit(benchmark::kMillisecond);

void BM_Factorize(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    IncrementalLogDet incremental(scene.weighted);
    benchmark::DoNotOptimize(incremental.base_log_det());
  }
}
BENCHMARK(BM_Factorize)->Unit(benchmark::kMillisecond);

// 100 Schur complements with every forward solve already cached (the per-frontier algebra alone).
void BM_DecisionLogDet_WarmCache(benchmark::State& state) {
  const Scene& scene = GetScene();
  IncrementalLogDet incremental(scene.weighted);
  for (const GraphExtension& extension : scene.extensions) incremental.LogDet(extension);
  for (auto _ : state) {
    for (const GraphExtension& extension : scene.extensions) {
      benchmark::DoNotOptimize(incremental.LogDet(extension));
    }
  }
}
BENCHMARK(BM_DecisionLogDet_WarmCache)->Unit(benchmark::kMillisecond);

// The same, from scratch: one CHOLMOD analyze + factorize per frontier.
void BM_DecisionLogDet_FromScratchSparse(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    for (const GraphExtension& extension : scene.extensions) {
      benchmark::DoNotOptimize(LogDetReducedLaplacianSparse(scene.weighted, extension));
    }
  }
  SceneCounters(state, scene);
}
BENCHMARK(BM_DecisionLogDet_FromScratchSparse)->Unit(benchmark::kMillisecond);

// Dense Eigen LLT, ONE candidate only (a decision would be 100×).
void BM_SingleCandidateLogDet_Dense(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    benchmark::DoNotOptimize(LogDetReducedLaplacianDense(scene.weighted, scene.extensions.front()));
  }
  SceneCounters(state, scene);
}
BENCHMARK(BM_SingleCandidateLogDet_Dense)->Unit(benchmark::kMillisecond)->Iterations(1);

// The hallucinated extensions of one decision (100 paths).
void BM_DecisionHallucinate(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    for (const auto& path : scene.paths_m) {
      benchmark::DoNotOptimize(HallucinatePath(scene.graph, path, scene.map, {}));
    }
  }
  SceneCounters(state, scene);
}
BENCHMARK(BM_DecisionHallucinate)->Unit(benchmark::kMillisecond);

// The whole U1 part of a decision: D-opt weights, 100 hallucinated paths, one
// factorization, 100 incremental log dets, U1 for each.
void BM_DecisionU1_Incremental(benchmark::State& state) {
  const Scene& scene = GetScene();
  for (auto _ : state) {
    const WeightedGraph weighted = ToWeightedGraph(scene.graph);
    IncrementalLogDet incremental(weighted);
    for (const auto& path : scene.paths_m) {
      const GraphExtension extension = HallucinatePath(scene.graph, path, scene.map, {});
      benchmark::DoNotOptimize(U1FromLogDet(incremental.LogDet(extension),
                                            weighted.num_nodes + extension.num_new_nodes));
    }
  }
  SceneCounters(state, scene);
}
BENCHMARK(BM_DecisionU1_Incremental)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
