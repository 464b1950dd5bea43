#include "eval/explore_runner.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "common/types_lcm.h"
#include "drivers/sim_config.h"
#include "drivers/sim_node.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_lcm.h"
#include "frontier/frontier_node.h"
#include "navigation/nav_config.h"
#include "navigation/nav_node.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"
#include "slam/trajectory_eval.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"
#include "worlds/worldgen.h"

namespace aslam {
namespace {

using Clock = std::chrono::steady_clock;

// Truth farther than this from a keyframe's time leaves it unplaced.
constexpr int64_t kTruthGap_us = 100000;

// Everything the runner learns from the bus, for evaluation only.
class Evaluator {
 public:
  Evaluator(lcm::LCM& lcm, const OccupancyGrid& truth_map)
      : truth_map_(truth_map), subscriptions_(lcm) {
    subscriptions_.Add<pose_t>(channels::kSimTruth, [this](const pose_t& m) {
      const auto pose = FromLcm(m);
      if (!pose) return false;
      truth_.push_back({pose->utime, pose->pose});
      return true;
    });
    subscriptions_.Add<sim_status_t>(channels::kSimStatus, [this](const sim_status_t& m) {
      collisions_ = m.collisions;
      return true;
    });
    subscriptions_.Add<pose_graph_t>(channels::kPoseGraph, [this](const pose_graph_t& m) {
      auto graph = FromLcm(m);
      if (!graph) return false;
      graph_ = std::move(*graph);
      loop_closures_ = m.loop_closures_accepted;
      return true;
    });
    subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) {
      const auto pose = FromLcm(m);
      if (!pose || graph_.nodes.empty()) return pose.has_value();
      // Kept relative to the newest keyframe, so the path follows later optimization.
      const PoseGraphNode& anchor = graph_.nodes.back();
      const Pose2d offset = anchor.pose.Between(pose->pose);
      if (!path_.empty()) {
        const Pose2d& last = path_.back().offset;
        if (path_.back().node == anchor.id && std::hypot(offset.x_m - last.x_m, offset.y_m - last.y_m) < 0.05) {
          return true;  // 5 cm apart is plenty for a drawing
        }
      }
      path_.push_back({anchor.id, offset});
      return true;
    });
    subscriptions_.Add<occupancy_grid_t>(channels::kSlamMap, [this](const occupancy_grid_t& m) {
      auto grid = FromLcm(m);
      if (!grid) return false;
      latest_map_ = std::move(*grid);
      coverage_stale_ = true;
      return true;
    });
    subscriptions_.Add<frontier_list_t>(channels::kFrontiers, [this](const frontier_list_t& m) {
      auto list = FromLcm(m);
      if (!list) return false;
      frontiers_ = std::move(*list);
      return true;
    });
    subscriptions_.Add<explore_status_t>(channels::kExploreStatus, [this](const explore_status_t& m) {
      status_ = m;
      if (m.state == explore_status_t::STATE_DONE) done_ = true;
      return true;
    });
    subscriptions_.Add<explore_goal_t>(channels::kExploreGoal, [this](const explore_goal_t& m) {
      goal_ = m;
      return true;
    });
  }

  // The SLAM map placed in the world by the true pose of the first keyframe.
  std::optional<Pose2d> MapInWorld() {
    if (!map_in_world_ && !graph_.nodes.empty()) {
      map_in_world_ = PoseAt(truth_, graph_.nodes.front().utime, kTruthGap_us);
    }
    return map_in_world_;
  }

  MapAgreement Agreement(const OccupancyGrid& map) {
    const auto map_in_world = MapInWorld();
    if (!map_in_world || map.empty()) return {};
    return ComputeMapAgreement(map, *map_in_world, truth_map_);
  }

  // Coverage of the newest SLAM_MAP, evaluated when asked (at most once per
  // simulated second) rather than for every map: it costs a pass over both grids.
  double coverage() {
    if (coverage_stale_ && latest_map_ && MapInWorld()) {
      coverage_ = Agreement(*latest_map_).coverage;
      coverage_stale_ = false;
    }
    return coverage_;
  }

  std::vector<Pose2d> Path(const PoseGraph& final_graph) const {
    std::vector<Pose2d> path;
    path.reserve(path_.size());
    for (const PathPoint& p : path_) {
      if (p.node < static_cast<int>(final_graph.nodes.size())) {
        path.push_back(final_graph.nodes[p.node].pose.Compose(p.offset));
      }
    }
    return path;
  }

  const std::vector<TimedPose>& truth() const { return truth_; }
  const PoseGraph& graph() const { return graph_; }
  const FrontierList& frontiers() const { return frontiers_; }
  const std::optional<explore_status_t>& status() const { return status_; }
  const std::optional<explore_goal_t>& goal() const { return goal_; }
  int loop_closures() const { return loop_closures_; }
  int64_t collisions() const { return collisions_; }
  bool done() const { return done_; }

 private:
  struct PathPoint {
    int node = 0;
    Pose2d offset;  // SLAM pose in the frame of keyframe `node`
  };
  const OccupancyGrid& truth_map_;
  Subscriptions subscriptions_;
  std::vector<TimedPose> truth_;
  std::optional<Pose2d> map_in_world_;
  PoseGraph graph_;
  std::vector<PathPoint> path_;
  FrontierList frontiers_;
  std::optional<explore_status_t> status_;
  std::optional<explore_goal_t> goal_;
  std::optional<OccupancyGrid> latest_map_;
  bool coverage_stale_ = false;
  double coverage_ = 0.0;
  int loop_closures_ = 0;
  int64_t collisions_ = 0;
  bool done_ = false;
};

std::string StateName(const std::optional<explore_status_t>& status) {
  if (!status) return "waiting";
  switch (status->state) {
    case explore_status_t::STATE_EXPLORING: return "exploring";
    case explore_status_t::STATE_DONE: return "done";
    default: return "waiting";
  }
}

}  // namespace

std::optional<Pose2d> ParsePose(const std::string& text) {
  std::istringstream in(text);
  Pose2d pose;
  char c1 = 0, c2 = 0;
  if (!(in >> pose.x_m >> c1 >> pose.y_m >> c2 >> pose.yaw_rad) || c1 != ',' || c2 != ',' ||
      !(in >> std::ws).eof() || !std::isfinite(pose.x_m) || !std::isfinite(pose.y_m) ||
      !std::isfinite(pose.yaw_rad)) {
    return std::nullopt;
  }
  return pose;
}

ExploreResult RunExploreInProcess(const ExploreOptions& options, const std::atomic<bool>* stop,
                                  const std::function<void(const ExploreProgress&)>& on_progress) {
  const auto method = ParseUtilityMethod(options.method);
  if (!method) throw std::invalid_argument("--method '" + options.method + "': expected fd, ags or ours");
  if (!(options.duration_s > 0)) throw std::invalid_argument("--duration must be > 0");

  // Every option is loaded and validated before anything runs (DESIGN §7.4).
  SimulatorOptions sim_options = LoadSimulatorOptionsFromFile(options.config_file);
  sim_options.seed = options.seed;
  const SlamConfig slam_config = LoadSlamConfigFromFile(options.config_file);
  const FrontierOptions frontier_options = LoadFrontierOptionsFromFile(options.config_file);
  UtilityOptions utility_options = LoadUtilityOptionsFromFile(options.config_file);
  utility_options.selector.method = *method;
  const NavOptions nav_options = LoadNavOptionsFromFile(options.config_file);

  const WorldInfo world = LoadWorld(options.world);
  Pose2d start = world.start;
  if (options.start) {
    start = *options.start;
    const CellIndex cell = world.map.grid.WorldToCell({start.x_m, start.y_m});
    if (world.map.grid.ValueOr(cell, OccupancyGrid::kOccupied) != OccupancyGrid::kFree) {
      throw std::invalid_argument("--start: not on a free cell of " + world.map_yaml_path);
    }
  } else if (!world.has_start) {
    throw std::invalid_argument(options.world + " has no world.yaml with a start: pass --start X,Y,YAW");
  }

  Simulator simulator(world.map.grid, start, sim_options);
  InProcessHost host;
  SimNode sim_node(host.lcm(), simulator, {options.world, std::nullopt});
  SlamNode slam_node(host.lcm(), slam_config.slam, slam_config.node);
  FrontierNode frontier_node(host.lcm(), frontier_options);
  UtilityNode utility_node(host.lcm(), utility_options);
  NavNode nav_node(host.lcm(), nav_options);
  Evaluator evaluator(host.lcm(), world.map.grid);

  ExploreResult result;
  const int64_t end_us = std::llround(options.duration_s * 1e6);
  const int64_t progress_us = std::llround(options.progress_period_s * 1e6);
  int64_t next_sample_us = 1'000'000;
  int64_t next_progress_us = progress_us;
  bool interrupted = false;
  const Clock::time_point wall_start = Clock::now();

  auto progress = [&] {
    ExploreProgress p;
    p.sim_s = simulator.utime() * 1e-6;
    p.wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
    p.coverage = evaluator.coverage();
    p.keyframes = static_cast<int>(evaluator.graph().nodes.size());
    p.loop_closures = evaluator.loop_closures();
    p.frontiers = static_cast<int>(evaluator.frontiers().frontiers.size());
    if (const auto& s = evaluator.status()) {
      p.goal_id = s->current_goal_id;
      p.goals_reached = s->goals_reached;
      p.goals_failed = s->goals_failed;
    }
    if (const auto& g = evaluator.goal(); g && !g->cancel && g->goal_id == p.goal_id) {
      p.goal_m = {g->x_m, g->y_m};
    }
    p.collisions = evaluator.collisions();
    p.state = StateName(evaluator.status());
    return p;
  };

  host.Run(
      [&] {
        if (simulator.utime() >= end_us) return false;
        sim_node.Tick();
        return true;
      },
      [&] {
        const int64_t now_us = simulator.utime();
        if (now_us >= next_sample_us) {
          result.coverage.push_back({now_us * 1e-6, evaluator.coverage()});
          next_sample_us += 1'000'000;
        }
        if (on_progress && progress_us > 0 && now_us >= next_progress_us) {
          on_progress(progress());
          next_progress_us += progress_us;
        }
        if (stop && stop->load()) {
          interrupted = true;
          return false;
        }
        return !evaluator.done();
      });
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();

  // The final state straight from SLAM: newer than its last (rate-limited) SLAM_MAP.
  result.map = slam_node.slam().RenderMap();
  result.graph = slam_node.slam().graph();
  if (const auto map_in_world = evaluator.MapInWorld()) result.map_in_world = *map_in_world;
  const MapAgreement agreement = evaluator.Agreement(result.map);
  const double sim_s = simulator.utime() * 1e-6;
  if (!result.coverage.empty() && result.coverage.back().t_s >= sim_s) result.coverage.pop_back();
  result.coverage.push_back({sim_s, agreement.coverage});
  result.slam_path = evaluator.Path(result.graph);
  for (const Frontier& f : evaluator.frontiers().frontiers) result.frontiers_m.push_back(f.points_m);

  RunMetrics& m = result.metrics;
  m.world = options.world;
  m.method = UtilityMethodName(*method);
  m.seed = options.seed;
  m.sim_seconds = sim_s;
  m.wall_seconds = wall_s;
  m.coverage = agreement.coverage;
  m.occupied_precision = agreement.occupied_precision;
  m.free_precision = agreement.free_precision;
  const double cell_area_m2 = world.map.grid.resolution_m() * world.map.grid.resolution_m();
  m.free_area_m2 = agreement.truth_free_cells > 0
                       ? agreement.truth_free_cells * cell_area_m2
                       : world.map.grid.CountCells().free * cell_area_m2;
  const AteResult ate = ComputeAte(KeyframePoses(result.graph), evaluator.truth());
  m.ate_rmse_m = ate.rmse_m;
  m.ate_max_m = ate.max_m;
  m.ate_matched = ate.matched;
  m.keyframes = static_cast<int>(result.graph.nodes.size());
  m.loop_closures = 0;
  for (const PoseGraphEdge& e : result.graph.edges) m.loop_closures += e.kind == EdgeKind::kLoopClosure;
  m.collisions = simulator.collisions();
  m.goals_reached = utility_node.goals_reached();
  m.goals_failed = utility_node.goals_failed();
  m.decisions = utility_node.decisions();
  m.done = evaluator.done();
  m.end_reason = m.done ? "done" : interrupted ? "interrupted" : "duration";
  for (const CoverageSample& s : result.coverage) {
    if (s.coverage >= 0.9) {
      m.time_to_90_coverage_s = s.t_s;
      break;
    }
  }
  if (on_progress) {
    ExploreProgress p = progress();
    p.coverage = m.coverage;
    p.keyframes = m.keyframes;
    p.loop_closures = m.loop_closures;
    p.collisions = m.collisions;
    p.wall_s = wall_s;
    on_progress(p);
  }
  return result;
}

}  // namespace aslam
