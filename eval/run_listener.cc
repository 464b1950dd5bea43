#include "eval/run_listener.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "aslam/frontier_list_t.hpp"
#include "aslam/lidar_scan_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "eval/graph_metrics.h"
#include "eval/map_metrics.h"
#include "eval/run_outputs.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_lcm.h"

namespace aslam {
namespace {

// Truth farther than this from a keyframe's time leaves it unplaced.
constexpr int64_t kTruthGap_us = 100000;

std::string StateName(const std::optional<explore_status_t>& status) {
  if (!status) return "waiting";
  switch (status->state) {
    case explore_status_t::STATE_EXPLORING: return "exploring";
    case explore_status_t::STATE_DONE: return "done";
    default: return "waiting";
  }
}

}  // namespace

RunListener::RunListener(lcm::LCM& lcm, const OccupancyGrid& truth_map, bool truth_on_host_clock)
    : truth_map_(truth_map), truth_on_host_clock_(truth_on_host_clock), subscriptions_(lcm) {
  subscriptions_.Add<pose_t>(channels::kSimTruth, [this](const pose_t& m) {
    const auto pose = FromLcm(m);
    if (!pose) return false;
    if (truth_.empty() || pose->utime > truth_.back().utime)
      truth_.push_back({pose->utime, pose->pose});
    if (!truth_on_host_clock_) Heard(pose->utime);
    const Point2d position{pose->pose.x_m, pose->pose.y_m};
    goals_.OnTruth(position);
    stuck_.OnPosition(sim_s(), position,
                      status_ && status_->state == explore_status_t::STATE_EXPLORING);
    return true;
  });
  if (truth_on_host_clock_) {
    subscriptions_.Add<lidar_scan_t>(channels::kLidarScan, [this](const lidar_scan_t& m) {
      auto scan = FromLcm(m);
      if (!scan) return false;
      if (scans_heard_++ % 3 == 0) scans_.push_back(std::move(*scan));
      return true;
    });
  }
  subscriptions_.Add<sim_status_t>(channels::kSimStatus, [this](const sim_status_t& m) {
    collisions_ = m.collisions;
    Heard(m.utime);
    return true;
  });
  subscriptions_.Add<pose_graph_t>(channels::kPoseGraph, [this](const pose_graph_t& m) {
    auto graph = FromLcm(m);
    if (!graph) return false;
    graph_ = std::move(*graph);
    d_opt_stale_ = true;
    loop_closures_ = m.loop_closures_accepted;
    return true;
  });
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) {
    const auto pose = FromLcm(m);
    if (!pose || graph_.nodes.empty()) return pose.has_value();
    // Kept relative to the newest keyframe, so the path follows later optimization.
    const PoseGraphNode& anchor = graph_.nodes.back();
    const Pose2d offset = anchor.pose.Between(pose->pose);
    if (!path_.empty() && path_.back().node == anchor.id &&
        std::hypot(offset.x_m - path_.back().offset.x_m, offset.y_m - path_.back().offset.y_m) <
            0.05) {
      return true;  // 5 cm apart is plenty for a drawing
    }
    path_.push_back({anchor.id, offset});
    return true;
  });
  AddMapSubscription(subscriptions_, channels::kSlamMap, [this](MapMessage m) {
    map_ = std::move(m.grid);
    coverage_stale_ = true;
    return true;
  });
  subscriptions_.Add<frontier_list_t>(channels::kFrontiers, [this](const frontier_list_t& m) {
    auto list = FromLcm(m);
    if (!list) return false;
    frontiers_ = std::move(*list);
    std::vector<int> ids;
    for (const Frontier& f : frontiers_.frontiers) ids.push_back(f.id);
    goals_.OnFrontiers(std::move(ids));
    return true;
  });
  subscriptions_.Add<explore_status_t>(channels::kExploreStatus, [this](const explore_status_t& m) {
    status_ = m;
    if (m.state == explore_status_t::STATE_DONE) done_ = true;
    if (m.state == explore_status_t::STATE_STOPPED) stopped_ = true;
    return true;
  });
  subscriptions_.Add<explore_goal_t>(channels::kExploreGoal, [this](const explore_goal_t& m) {
    goal_ = m;
    goals_.OnGoal(sim_s(), m.goal_id, m.cancel, {m.x_m, m.y_m}, m.frontier_id);
    return true;
  });
  subscriptions_.Add<nav_status_t>(channels::kNavStatus, [this](const nav_status_t& m) {
    const auto status = FromLcm(m);
    if (!status) return false;
    goals_.OnNavStatus(sim_s(), status->goal_id, status->state, status->detail);
    return true;
  });
  subscriptions_.Add<utility_scores_t>(channels::kUtilityScores, [this](const utility_scores_t& m) {
    double path_length_m = -1.0;
    for (const frontier_score_t& score : m.scores) {
      if (score.frontier_id == m.chosen_frontier_id) path_length_m = score.path_length_m;
    }
    goals_.OnScores(m.chosen_frontier_id, path_length_m);
    return true;
  });
}

void RunListener::Heard(int64_t utime) {
  heard_sim_ = true;
  sim_utime_ = std::max(sim_utime_, utime);
}

std::optional<Pose2d> RunListener::MapInWorld() {
  if (!map_in_world_ && !graph_.nodes.empty()) {
    map_in_world_ = PoseAt(truth_, graph_.nodes.front().utime, kTruthGap_us);
  }
  return map_in_world_;
}

MapAgreement RunListener::Agreement(const OccupancyGrid& map) {
  const auto map_in_world = MapInWorld();
  if (!map_in_world || map.empty()) return {};
  return ComputeMapAgreement(map, *map_in_world, truth_map_);
}

double RunListener::coverage() {
  if (coverage_stale_ && map_ && MapInWorld()) {
    if (!coverage_evaluator_) coverage_evaluator_.emplace(truth_map_, *MapInWorld());
    coverage_ = coverage_evaluator_->Evaluate(*map_).fraction;
    coverage_stale_ = false;
  }
  return coverage_;
}

double RunListener::mean_edge_d_opt() {
  if (d_opt_stale_) {
    mean_edge_d_opt_ = MeanEdgeDOptimality(graph_);
    d_opt_stale_ = false;
  }
  return graph_.edges.empty() ? std::nan("") : mean_edge_d_opt_;
}

ExploreProgress RunListener::FinalProgress(const RunMetrics& metrics, double sim_s, double wall_s) {
  ExploreProgress p = Progress(sim_s, wall_s);
  p.coverage = metrics.coverage;
  p.keyframes = metrics.keyframes;
  p.loop_closures = metrics.loop_closures;
  p.collisions = metrics.collisions;
  return p;
}

std::vector<Pose2d> RunListener::Path(const PoseGraph& graph) const {
  std::vector<Pose2d> path;
  path.reserve(path_.size());
  for (const PathPoint& p : path_) {
    if (p.node >= 0 && p.node < static_cast<int>(graph.nodes.size())) {
      path.push_back(graph.nodes[p.node].pose.Compose(p.offset));
    }
  }
  return path;
}

ExploreProgress RunListener::Progress(double sim_s, double wall_s) {
  ExploreProgress p;
  p.sim_s = sim_s;
  p.wall_s = wall_s;
  p.coverage = coverage();
  p.keyframes = static_cast<int>(graph_.nodes.size());
  p.loop_closures = loop_closures_;
  p.frontiers = static_cast<int>(frontiers_.frontiers.size());
  if (status_) {
    p.goal_id = status_->current_goal_id;
    p.goals_reached = status_->goals_reached;
    p.goals_failed = status_->goals_failed;
  }
  if (goal_ && !goal_->cancel && goal_->goal_id == p.goal_id) p.goal_m = {goal_->x_m, goal_->y_m};
  p.collisions = collisions_;
  p.state = StateName(status_);
  return p;
}

Pose2d ResolveStart(const WorldInfo& world, const ExploreOptions& options) {
  if (!options.start) {
    if (!world.has_start) {
      throw std::invalid_argument(options.world +
                                  " has no world.yaml with a start: pass --start X,Y,YAW");
    }
    return world.start;
  }
  const Pose2d start = *options.start;
  const CellIndex cell = world.map.grid.WorldToCell({start.x_m, start.y_m});
  if (world.map.grid.ValueOr(cell, OccupancyGrid::kOccupied) != OccupancyGrid::kFree) {
    throw std::invalid_argument("--start: not on a free cell of " + world.map_yaml_path);
  }
  return start;
}

void FinishResult(RunListener& listener, const WorldInfo& world, const ExploreOptions& options,
                  const std::string& method, double sim_s, double wall_s, ExploreResult* result) {
  if (const auto map_in_world = listener.MapInWorld()) result->map_in_world = *map_in_world;
  const MapAgreement agreement = listener.Agreement(result->map);
  if (!result->coverage.empty() && result->coverage.back().t_s >= sim_s)
    result->coverage.pop_back();
  result->coverage.push_back({sim_s, agreement.coverage});
  const double final_d_opt =
      result->graph.edges.empty() ? std::nan("") : MeanEdgeDOptimality(result->graph);
  if (!result->uncertainty.empty() && result->uncertainty.back().t_s >= sim_s)
    result->uncertainty.pop_back();
  result->uncertainty.push_back({sim_s, final_d_opt});
  result->slam_path = listener.Path(result->graph);
  for (const Frontier& f : listener.frontiers().frontiers)
    result->frontiers_m.push_back(f.points_m);

  RunMetrics& m = result->metrics;
  m.world = options.world;
  m.method = method;
  m.seed = options.seed;
  m.sim_seconds = sim_s;
  m.wall_seconds = wall_s;
  m.coverage = agreement.coverage;
  m.occupied_precision = agreement.occupied_precision;
  m.free_precision = agreement.free_precision;
  const double cell_area_m2 = world.map.grid.resolution_m() * world.map.grid.resolution_m();
  m.free_area_m2 = agreement.truth_free_cells > 0 ? agreement.truth_free_cells * cell_area_m2
                                                  : world.map.grid.CountCells().free * cell_area_m2;
  const AteResult ate = ComputeAte(KeyframePoses(result->graph), listener.truth());
  m.ate_rmse_m = ate.rmse_m;
  m.ate_max_m = ate.max_m;
  m.ate_matched = ate.matched;
  if (!listener.scans().empty()) {
    m.scan_timing =
        EstimateScanTiming(listener.scans(), listener.truth(), SimWorld(world.map.grid));
  }
  m.keyframes = static_cast<int>(result->graph.nodes.size());
  m.loop_closures = 0;
  for (const PoseGraphEdge& e : result->graph.edges)
    m.loop_closures += e.kind == EdgeKind::kLoopClosure;
  m.done = listener.done();
  result->goals = listener.goals().goals();
  for (const auto& [outcome, count] : listener.goals().CountByOutcome())
    m.goal_outcomes.emplace_back(GoalOutcomeName(outcome), count);
  m.goal_failures_by_reason = listener.goals().CountFailuresByReason();
  m.stuck_episodes = listener.stuck().episodes();
  m.stuck_s = listener.stuck().StuckSeconds(sim_s);
  m.time_to_90_coverage_s = TimeToCoverage(result->coverage, 0.9);

  m.average_degree = AverageDegree(result->graph);
  m.algebraic_connectivity = AlgebraicConnectivity(result->graph);
  m.normalized_tree_connectivity = NormalizedTreeConnectivity(result->graph);
  m.map_in_world = result->map_in_world;
  const MapQuality quality = CompareMapToTruth(result->map, result->map_in_world, world.map.grid);
  m.ssim = quality.ssim;
  m.map_rmse = quality.rmse;
  m.mean_edge_d_opt = final_d_opt;
  std::vector<double> d_opt_series;
  for (const UncertaintySample& s : result->uncertainty) d_opt_series.push_back(s.mean_edge_d_opt);
  const UncertaintyReduction reduction = ComputeUncertaintyReduction(d_opt_series);
  m.d_opt_max = reduction.max;
  m.d_opt_min = reduction.min;
  m.d_opt_difference = reduction.difference;
  m.d_opt_reduction_percent = reduction.percent_reduction;
}

}  // namespace aslam
