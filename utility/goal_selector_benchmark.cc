// One goal decision (issue #5): 100 frontiers on a 5000-node pose graph, on the
// office and campus worlds. The whole GoalSelector::Decide for fd, ags and
// ours; the same decision's parts timed one by one (counters, ms per decision);
// and the U1 log dets three ways side by side: incremental, from scratch with
// CHOLMOD per candidate, dense Eigen for one candidate (full N = 5000).
//
//   build/utility/goal_selector_benchmark --benchmark_repetitions=3
//       --benchmark_report_aggregates_only=true   (one line)
//
// Scene (deterministic, built once per world): the map is the world's ground
// truth (no SLAM run: everything inside the building is known, only the outer
// margin is unknown); the graph is a long synthetic SLAM run of the same shape:
// keyframes every 0.3 m along planned paths between random reachable cells,
// odometry edges between consecutive keyframes, and on revisits (every 5th
// keyframe) loop closures to up to 2 keyframes >= 30 older within 1 m. The
// robot is at the newest keyframe; the 100 frontier targets are random cells
// reachable from it.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/world_file.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"
#include "utility/benchmark_scene.h"
#include "utility/goal_selector.h"
#include "utility/hallucination.h"
#include "utility/path_entropy.h"
#include "utility/spanning_trees.h"

namespace aslam {
namespace {

constexpr int kNumNodes = 5000;
constexpr int kNumFrontiers = 100;
constexpr double kKeyframeSpacing_m = 0.3;

struct Scene {
  OccupancyGrid map;
  PoseGraph graph;
  Pose2d robot;
  std::vector<Frontier> frontiers;
  int num_loop_closures = 0;
  // U1 inputs of one decision (the paths Decide plans), for the log-det comparison.
  std::vector<std::vector<Point2d>> paths_m;
  WeightedGraph weighted;
  std::vector<GraphExtension> extensions;
};

Scene BuildScene(const std::string& world_name) {
  Scene s;
  const WorldInfo world = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/" + world_name);
  s.map = world.map.grid;
  const Costmap costmap(s.map, CostmapOptions{});
  const GlobalPlanner planner;
  const CellIndex start = s.map.WorldToCell({world.start.x_m, world.start.y_m});
  std::vector<CellIndex> reachable;
  {
    const ShortestPathTree tree = planner.Search(costmap, start);
    for (int row = 0; row < s.map.height_cells(); ++row) {
      for (int col = 0; col < s.map.width_cells(); ++col) {
        if (tree.Reachable({col, row})) reachable.push_back({col, row});
      }
    }
  }
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, reachable.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // The run: drive planned paths between random reachable cells, a keyframe every 0.3 m.
  Point2d at = s.map.CellCenter(start);
  while (static_cast<int>(s.graph.nodes.size()) < kNumNodes) {
    const Point2d goal = s.map.CellCenter(reachable[pick(rng)]);
    const auto path = planner.Plan(costmap, at, goal);
    if (!path) continue;
    double travelled_m = kKeyframeSpacing_m;
    const auto& p = path->points_m;
    for (std::size_t i = 1; i < p.size() && static_cast<int>(s.graph.nodes.size()) < kNumNodes;
         ++i) {
      travelled_m += std::hypot(p[i].x_m - p[i - 1].x_m, p[i].y_m - p[i - 1].y_m);
      if (travelled_m < kKeyframeSpacing_m) continue;
      travelled_m = 0.0;
      const int id = static_cast<int>(s.graph.nodes.size());
      const double yaw = std::atan2(p[i].y_m - p[i - 1].y_m, p[i].x_m - p[i - 1].x_m);
      s.graph.nodes.push_back({id, 0, {p[i].x_m, p[i].y_m, yaw}});
      if (id > 0) {
        PoseGraphEdge edge;
        edge.from_id = id - 1;
        edge.to_id = id;
        edge.measurement = s.graph.nodes[id - 1].pose.Between(s.graph.nodes[id].pose);
        edge.information = SyntheticEdgeInformation(0.02 + 0.02 * unit(rng),
                                                    0.005 + 0.01 * unit(rng), unit(rng) * M_PI);
        s.graph.edges.push_back(edge);
      }
      if (id % 5 != 0) continue;
      int closures = 0;
      for (int j = 0; j + 30 < id && closures < 2; j += 3) {
        const Pose2d& a = s.graph.nodes[j].pose;
        const Pose2d& b = s.graph.nodes[id].pose;
        if (std::hypot(a.x_m - b.x_m, a.y_m - b.y_m) >= 1.0) continue;
        PoseGraphEdge edge;
        edge.from_id = j;
        edge.to_id = id;
        edge.kind = EdgeKind::kLoopClosure;
        edge.measurement = a.Between(b);
        edge.information = SyntheticEdgeInformation(0.04 + 0.04 * unit(rng),
                                                    0.01 + 0.02 * unit(rng), unit(rng) * M_PI);
        s.graph.edges.push_back(edge);
        ++closures;
        ++s.num_loop_closures;
      }
    }
    at = goal;
  }
  s.robot = s.graph.nodes.back().pose;

  // Frontier targets: random cells reachable from the robot.
  const ShortestPathTree from_robot =
      planner.Search(costmap, s.map.WorldToCell({s.robot.x_m, s.robot.y_m}));
  while (static_cast<int>(s.frontiers.size()) < kNumFrontiers) {
    const CellIndex cell = reachable[pick(rng)];
    if (!from_robot.Reachable(cell)) continue;
    Frontier frontier;
    frontier.id = static_cast<int>(s.frontiers.size());
    frontier.target_m = s.map.CellCenter(cell);
    s.frontiers.push_back(frontier);
  }

  // The extensions a decision scores (paths from the one search, as Decide plans them).
  s.weighted = ToWeightedGraph(s.graph);
  for (const Frontier& frontier : s.frontiers) {
    if (const auto path = from_robot.PathTo(s.map.WorldToCell(frontier.target_m))) {
      s.paths_m.push_back(path->points_m);
      s.extensions.push_back(
          HallucinatePath(s.graph, path->points_m, s.map, HallucinationOptions{}));
    }
  }
  // Sanity: incremental equals from scratch on every candidate (issue #5).
  AbortUnlessIncrementalMatchesSparse(s.weighted, s.extensions, world_name.c_str());
  return s;
}

const Scene& GetScene(const std::string& world_name) {
  static std::map<std::string, std::unique_ptr<Scene>> scenes;
  auto& scene = scenes[world_name];
  if (!scene) scene = std::make_unique<Scene>(BuildScene(world_name));
  return *scene;
}

const char* WorldName(int64_t index) { return index == 0 ? "office" : "campus"; }

void SceneCounters(benchmark::State& state, const Scene& scene) {
  int new_nodes = 0, edges = 0;
  for (const GraphExtension& e : scene.extensions) {
    new_nodes += e.num_new_nodes;
    edges += static_cast<int>(e.edges.size());
  }
  state.counters["nodes"] = static_cast<double>(scene.graph.nodes.size());
  state.counters["graph_closures"] = scene.num_loop_closures;
  state.counters["frontiers"] = static_cast<double>(scene.frontiers.size());
  state.counters["halluc_closures"] = edges - new_nodes;
}

// --- The whole decision, as the utility node makes it (one selector kept across decisions). ---
void BM_Decision(benchmark::State& state, UtilityMethod method) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  GoalSelectorOptions options;
  options.method = method;
  GoalSelector selector(options);
  GoalDecision decision;
  for (auto _ : state) {
    decision = selector.Decide(scene.map, scene.robot, scene.graph, scene.frontiers, {});
    benchmark::DoNotOptimize(decision.chosen_index);
  }
  SceneCounters(state, scene);
  state.counters["eligible"] = decision.num_eligible;
  state.counters["chosen_id"] = decision.has_goal() ? decision.chosen().frontier_id : -1;
}
BENCHMARK_CAPTURE(BM_Decision, fd, UtilityMethod::kFd)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Decision, ags, UtilityMethod::kAgs)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Decision, ours, UtilityMethod::kOurs)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

// --- The ours decision taken apart: the calls Decide makes, each timed (counters: ms per
// decision). costmap; search (the one-to-all Dijkstra, goal cells and paths); U1 (D-opt
// weights, factorization, 100 hallucinated paths and incremental log dets); U2 (100 rays).
void BM_DecisionParts(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  const GoalSelectorOptions options;
  const GlobalPlanner planner(options.global_planner);
  Costmap costmap;  // kept across decisions, as GoalSelector keeps it
  ShortestPathTree tree;
  using Clock = std::chrono::steady_clock;
  double costmap_s = 0, search_s = 0, u1_s = 0, u2_s = 0;
  auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  const CellIndex robot_cell = scene.map.WorldToCell({scene.robot.x_m, scene.robot.y_m});
  std::vector<CellIndex> targets;
  for (const Frontier& f : scene.frontiers) targets.push_back(scene.map.WorldToCell(f.target_m));
  for (auto _ : state) {
    const auto t0 = Clock::now();
    costmap.Rebuild(scene.map, options.costmap);
    const auto t1 = Clock::now();
    planner.Search(costmap, robot_cell, targets, &tree);  // every target is traversable here
    std::vector<GlobalPath> paths;
    for (const CellIndex& target : targets) {
      if (auto path = tree.PathTo(target)) paths.push_back(std::move(*path));
    }
    const auto t2 = Clock::now();
    const WeightedGraph weighted = ToWeightedGraph(scene.graph);
    IncrementalLogDet incremental(weighted);
    std::vector<double> u1(paths.size());
    for (std::size_t i = 0; i < paths.size(); ++i) {
      const GraphExtension extension =
          HallucinatePath(scene.graph, paths[i].points_m, scene.map, options.hallucination);
      u1[i] =
          U1FromLogDet(incremental.LogDet(extension), weighted.num_nodes + extension.num_new_nodes);
    }
    const auto t3 = Clock::now();
    for (std::size_t i = 0; i < targets.size(); ++i) {
      benchmark::DoNotOptimize(ComputeU2(scene.map, robot_cell, targets[i],
                                         i < u1.size() ? u1[i] : 0.0, options.path_entropy));
    }
    const auto t4 = Clock::now();
    costmap_s += seconds(t0, t1);
    search_s += seconds(t1, t2);
    u1_s += seconds(t2, t3);
    u2_s += seconds(t3, t4);
  }
  const double per_ms = 1e3 / static_cast<double>(state.iterations());
  state.counters["costmap_ms"] = costmap_s * per_ms;
  state.counters["search_ms"] = search_s * per_ms;
  state.counters["U1_ms"] = u1_s * per_ms;
  state.counters["U2_ms"] = u2_s * per_ms;
  SceneCounters(state, scene);
}
BENCHMARK(BM_DecisionParts)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// U1 parts alone: D-opt weights of the graph, the factorization, the 100 hallucinated paths.
void BM_U1_Weights(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(ToWeightedGraph(scene.graph));
}
BENCHMARK(BM_U1_Weights)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_U1_Hallucinate(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  for (auto _ : state) {
    for (const auto& path : scene.paths_m) {
      benchmark::DoNotOptimize(
          HallucinatePath(scene.graph, path, scene.map, HallucinationOptions{}));
    }
  }
}
BENCHMARK(BM_U1_Hallucinate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_U1_Factorize(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  for (auto _ : state) {
    IncrementalLogDet incremental(scene.weighted);
    benchmark::DoNotOptimize(incremental.base_log_det());
  }
}
BENCHMARK(BM_U1_Factorize)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// --- U1 log dets of one decision, three ways side by side (the same extensions). ---
// Incremental: one factorization + 100 Schur complements from cached solves.
void BM_LogDet_Incremental(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  int cached = 0;
  for (auto _ : state) {
    IncrementalLogDet incremental(scene.weighted);
    for (const GraphExtension& extension : scene.extensions) {
      benchmark::DoNotOptimize(incremental.LogDet(extension));
    }
    cached = incremental.cached_solves();
  }
  SceneCounters(state, scene);
  state.counters["candidates"] = static_cast<double>(scene.extensions.size());
  state.counters["cached_solves"] = cached;
}
BENCHMARK(BM_LogDet_Incremental)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// From scratch: one CHOLMOD analyze + factorize per candidate.
void BM_LogDet_FromScratchSparse(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  for (auto _ : state) {
    for (const GraphExtension& extension : scene.extensions) {
      benchmark::DoNotOptimize(LogDetReducedLaplacianSparse(scene.weighted, extension));
    }
  }
  SceneCounters(state, scene);
  state.counters["candidates"] = static_cast<double>(scene.extensions.size());
}
BENCHMARK(BM_LogDet_FromScratchSparse)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Dense Eigen LLT of the full 5000-node system, ONE candidate only (a decision would be 100×).
void BM_LogDet_DenseOneCandidate(benchmark::State& state) {
  const Scene& scene = GetScene(WorldName(state.range(0)));
  state.SetLabel(WorldName(state.range(0)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(LogDetReducedLaplacianDense(scene.weighted, scene.extensions.front()));
  }
  state.counters["candidates"] = 1;
}
BENCHMARK(BM_LogDet_DenseOneCandidate)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
