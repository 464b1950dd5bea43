// Back-end timings: pose-graph optimization of a 5000-node / 500-loop-closure
// graph (cold from odometry, and warm after one new loop closure), and the
// occupancy mapper (one 720-beam scan; re-rendering 1000 keyframes).
//
//   OMP_NUM_THREADS=1 build-be/slam/pose_graph_benchmark
// (CHOLMOD may use OpenMP; one thread makes the CPU column the whole cost.)

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "slam/occupancy_mapper.h"
#include "slam/pose_graph_optimizer.h"
#include "slam/submap_map.h"

namespace aslam {
namespace {

constexpr int kNodes = 5000;
constexpr int kLoopClosures = 500;
constexpr double kStepM = 0.3;  // keyframe spacing

Eigen::Matrix3d Information(double sigma_xy_m, double sigma_yaw_rad) {
  return Eigen::Vector3d(1.0 / (sigma_xy_m * sigma_xy_m), 1.0 / (sigma_xy_m * sigma_xy_m),
                         1.0 / (sigma_yaw_rad * sigma_yaw_rad))
      .asDiagonal();
}

struct SyntheticGraph {
  PoseGraph odometry_only;                   // initial guess by dead reckoning, no closures
  std::vector<PoseGraphEdge> loop_closures;  // ordered by their newer node
};

// ~30 laps round a wobbling circle (radius 6..10 m), keyframes every 0.3 m,
// noisy odometry; loop closures between revisits more than 100 nodes apart.
SyntheticGraph MakeGraph() {
  std::mt19937 rng(42);
  std::vector<Pose2d> truth;
  double angle = 0.0;
  for (int i = 0; i < kNodes; ++i) {
    const double radius_m = 8.0 + 2.0 * std::sin(0.37 * angle);
    truth.push_back(
        {radius_m * std::cos(angle), radius_m * std::sin(angle), WrapAngle(angle + M_PI / 2)});
    angle += kStepM / radius_m;
  }
  SyntheticGraph out;
  std::normal_distribution<double> odo_xy(0.0, 0.01), odo_yaw(0.0, 0.005);
  PoseGraph& graph = out.odometry_only;
  graph.nodes.push_back({0, 0, truth[0]});
  for (int i = 1; i < kNodes; ++i) {
    PoseGraphEdge edge;
    edge.from_id = i - 1;
    edge.to_id = i;
    const Pose2d delta = truth[i - 1].Between(truth[i]);
    edge.measurement = {delta.x_m + odo_xy(rng), delta.y_m + odo_xy(rng),
                        WrapAngle(delta.yaw_rad + odo_yaw(rng))};
    edge.information = Information(0.01, 0.005);
    graph.edges.push_back(edge);
    graph.nodes.push_back({i, 0, graph.nodes[i - 1].pose.Compose(edge.measurement)});
  }
  // One closure per chosen newer node, to a random older revisit within 0.5 m.
  std::normal_distribution<double> lc_xy(0.0, 0.02), lc_yaw(0.0, 0.01);
  std::vector<int> newer(kNodes - 200);
  for (int j = 0; j < static_cast<int>(newer.size()); ++j) newer[j] = j + 200;
  std::shuffle(newer.begin(), newer.end(), rng);
  for (int j : newer) {
    if (static_cast<int>(out.loop_closures.size()) == kLoopClosures) break;
    std::vector<int> candidates;
    for (int i = 0; i < j - 100; ++i) {
      if (std::hypot(truth[i].x_m - truth[j].x_m, truth[i].y_m - truth[j].y_m) < 0.5) {
        candidates.push_back(i);
      }
    }
    if (candidates.empty()) continue;
    const int i = candidates[std::uniform_int_distribution<int>(0, candidates.size() - 1)(rng)];
    PoseGraphEdge edge;
    edge.from_id = j;
    edge.to_id = i;
    edge.kind = EdgeKind::kLoopClosure;
    const Pose2d delta = truth[j].Between(truth[i]);
    edge.measurement = {delta.x_m + lc_xy(rng), delta.y_m + lc_xy(rng),
                        WrapAngle(delta.yaw_rad + lc_yaw(rng))};
    edge.information = Information(0.02, 0.01);
    out.loop_closures.push_back(edge);
  }
  std::sort(out.loop_closures.begin(), out.loop_closures.end(),
            [](const PoseGraphEdge& a, const PoseGraphEdge& b) { return a.from_id < b.from_id; });
  return out;
}

const SyntheticGraph& Graph() {
  static const SyntheticGraph graph = MakeGraph();
  return graph;
}

void ReportSummary(benchmark::State& state, const OptimizationSummary& summary) {
  state.counters["iterations"] = summary.iterations;
  state.counters["final_cost"] = summary.final_cost;
  state.counters["usable"] = summary.usable;
}

// (a) All 500 closures at once, from the dead-reckoning initial guess.
void BM_OptimizeCold(benchmark::State& state) {
  PoseGraph start = Graph().odometry_only;
  for (const PoseGraphEdge& edge : Graph().loop_closures) start.edges.push_back(edge);
  const PoseGraphOptimizer optimizer({});
  OptimizationSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    PoseGraph graph = start;
    state.ResumeTiming();
    summary = optimizer.Optimize(&graph);
  }
  ReportSummary(state, summary);
}
BENCHMARK(BM_OptimizeCold)->Unit(benchmark::kMillisecond);

// (b) The realistic case: the graph with 499 closures was optimized, a new
// closure arrives and the solve starts from the previous optimum. The
// argument is -log10(function_tolerance): 6 is the default.
void BM_OptimizeWarmAfterOneLoopClosure(benchmark::State& state) {
  PoseGraph start = Graph().odometry_only;
  for (int k = 0; k + 1 < kLoopClosures; ++k) start.edges.push_back(Graph().loop_closures[k]);
  // Converge first (the front end optimized after each earlier closure).
  for (int pass = 0; pass < 3; ++pass) PoseGraphOptimizer({}).Optimize(&start);
  start.edges.push_back(Graph().loop_closures.back());
  PoseGraphOptimizerOptions options;
  options.function_tolerance = std::pow(10.0, -static_cast<double>(state.range(0)));
  const PoseGraphOptimizer optimizer(options);
  OptimizationSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    PoseGraph graph = start;
    state.ResumeTiming();
    summary = optimizer.Optimize(&graph);
  }
  ReportSummary(state, summary);
  state.counters["ceres_s"] = summary.solve_time_s;
}
BENCHMARK(BM_OptimizeWarmAfterOneLoopClosure)->Arg(6)->Arg(4)->Unit(benchmark::kMillisecond);

// --- mapper ---

struct Segment {
  double x0, y0, x1, y1;
};

// A 20 m x 14 m office: outer walls, two partitions with doorways, a pillar.
const std::vector<Segment>& Walls() {
  static const std::vector<Segment> walls = {
      {-10, -7, 10, -7}, {10, -7, 10, 7}, {10, 7, -10, 7}, {-10, 7, -10, -7},
      {-3, -7, -3, -1},  {-3, 1, -3, 7},  {4, 7, 4, 2},    {4, 0, 4, -7},
      {1, -2, 2, -2},    {2, -2, 2, -3},  {2, -3, 1, -3},  {1, -3, 1, -2},
  };
  return walls;
}

LidarScan SimulateScan(const Pose2d& pose) {
  LidarScan scan;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2.0 * M_PI / 720;
  scan.range_min_m = 0.1;
  scan.range_max_m = 12.0;
  scan.range_m.resize(720);
  for (int i = 0; i < 720; ++i) {
    const double a = pose.yaw_rad + scan.BeamAngle(i);
    const double ux = std::cos(a), uy = std::sin(a);
    double best = 1e9;
    for (const Segment& s : Walls()) {
      // Solve pose + t·u = p0 + q·(p1 − p0) for t ≥ 0, q in [0, 1].
      const double dx = s.x1 - s.x0, dy = s.y1 - s.y0;
      const double den = ux * (-dy) - uy * (-dx);
      if (std::abs(den) < 1e-12) continue;
      const double rx = s.x0 - pose.x_m, ry = s.y0 - pose.y_m;
      const double t = (rx * (-dy) - ry * (-dx)) / den;
      const double q = (ux * ry - uy * rx) / den;
      if (t > 0 && q >= 0 && q <= 1) best = std::min(best, t);
    }
    scan.range_m[i] = best <= scan.range_max_m ? static_cast<float>(best) : 0.0f;
  }
  return scan;
}

struct Keyframes {
  std::vector<Pose2d> poses;
  std::vector<LidarScan> scans;
};

// 1000 keyframes wandering through the office's three rooms.
const Keyframes& OfficeKeyframes() {
  static const Keyframes keyframes = [] {
    Keyframes k;
    for (int i = 0; i < 1000; ++i) {
      const double t = 2.0 * M_PI * i / 250.0;
      const Pose2d pose{7.0 * std::sin(t), 4.5 * std::sin(2.0 * t) * 0.9, WrapAngle(t)};
      k.poses.push_back(pose);
      k.scans.push_back(SimulateScan(pose));
    }
    return k;
  }();
  return keyframes;
}

void BM_MapperInsertScan(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  OccupancyMapper mapper({});
  for (int i = 0; i < 50; ++i) mapper.InsertScan(k.poses[i], k.scans[i]);  // grid grown
  std::size_t i = 0;
  for (auto _ : state) {
    mapper.InsertScan(k.poses[i % k.poses.size()], k.scans[i % k.poses.size()]);
    ++i;
  }
}
BENCHMARK(BM_MapperInsertScan)->Unit(benchmark::kMicrosecond);

// map_thinning's test of every keyframe: the unknown inserting it would reveal, on a mapped floor.
void BM_MapperCountRevealedCells(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  OccupancyMapper mapper({});
  for (std::size_t i = 0; i < k.poses.size(); ++i) mapper.InsertScan(k.poses[i], k.scans[i]);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        mapper.CountRevealedCells(k.poses[i % k.poses.size()], k.scans[i % k.poses.size()]));
    ++i;
  }
}
BENCHMARK(BM_MapperCountRevealedCells)->Unit(benchmark::kMicrosecond);

// Every keyframe re-inserted into one grid: what a large closure cost before submaps.
void BM_MapperRerender1000Keyframes(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  OccupancyMapper mapper({});
  for (auto _ : state) {
    mapper.Clear();
    for (std::size_t i = 0; i < k.poses.size(); ++i) mapper.InsertScan(k.poses[i], k.scans[i]);
    benchmark::DoNotOptimize(mapper.Render());
  }
}
BENCHMARK(BM_MapperRerender1000Keyframes)->Unit(benchmark::kMillisecond);

// What a closure costs per submap it moved: one submap of 20 keyframes rebuilt.
void BM_SubmapRerender(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  SubmapMap map({});
  std::vector<SubmapMap::PosedScan> first_submap;
  for (std::size_t i = 0; i < k.poses.size(); ++i) {
    if (map.InsertScan(k.poses[i], k.scans[i]) == 0)
      first_submap.push_back({k.poses[i], &k.scans[i]});
  }
  for (auto _ : state) map.RerenderSubmap(0, first_submap);
}
BENCHMARK(BM_SubmapRerender)->Unit(benchmark::kMillisecond);

// SLAM's map per new keyframe: one more scan, then the map rendered (the scan's cells only).
void BM_SubmapMapInsertAndRender(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  SubmapMap map({});
  for (std::size_t i = 0; i < k.poses.size(); ++i) map.InsertScan(k.poses[i], k.scans[i]);
  benchmark::DoNotOptimize(map.Render());
  std::size_t next = 0;
  for (auto _ : state) {
    map.InsertScan(k.poses[next], k.scans[next]);
    next = (next + 1) % k.poses.size();
    benchmark::DoNotOptimize(map.Render());
  }
}
BENCHMARK(BM_SubmapMapInsertAndRender)->Unit(benchmark::kMillisecond);

// Every cell rendered: the first render, or one after a closure moved the whole map.
void BM_SubmapMapRender(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  std::optional<SubmapMap> map;
  for (auto _ : state) {
    state.PauseTiming();
    map.reset();  // freeing the submaps is not rendering
    map.emplace(OccupancyMapperOptions{});
    for (std::size_t i = 0; i < k.poses.size(); ++i) map->InsertScan(k.poses[i], k.scans[i]);
    state.ResumeTiming();
    benchmark::DoNotOptimize(map->Render());
  }
}
BENCHMARK(BM_SubmapMapRender)->Unit(benchmark::kMillisecond);

void BM_MapperRender(benchmark::State& state) {
  const Keyframes& k = OfficeKeyframes();
  OccupancyMapper mapper({});
  for (std::size_t i = 0; i < k.poses.size(); ++i) mapper.InsertScan(k.poses[i], k.scans[i]);
  for (auto _ : state) benchmark::DoNotOptimize(mapper.Render());
  const OccupancyGrid grid = mapper.Render();
  state.counters["cells"] = static_cast<double>(grid.cells().size());
}
BENCHMARK(BM_MapperRender)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace aslam

BENCHMARK_MAIN();
