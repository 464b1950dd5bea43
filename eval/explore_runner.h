#pragma once

// `aslam explore --inproc`: every node (simulator, SLAM, frontier, utility,
// navigation) on one InProcessHost memq:// bus, ticked by the simulator
// (docs/architecture.md §4), deterministic for a seed and as fast as the CPU allows.
//
// The runner alone listens to SIM_TRUTH and SIM_STATUS, for evaluation
// (coverage and ATE, docs/architecture.md §6); the algorithm nodes never see them. It
// reads the wall clock only for wall_seconds and the progress line.

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"  // also ParsePose, for --start
#include "common/pose_graph.h"
#include "eval/goal_ledger.h"
#include "eval/scan_timing.h"
#include "eval/stuck_detector.h"
#include "procman/process_history.h"
#include "utility/goal_selector.h"

namespace aslam {

// What `--method` names: a utility method (fd, ags, ours), or `ideal`, the ideal explorer
// (evaluation only: the true pose and lidar instead of SLAM, eval/ideal_mapper.h, and fd's
// nearest frontier by path), the physical limit every method is measured against.
struct ExploreMethod {
  UtilityMethod utility = UtilityMethod::kOurs;
  bool ideal = false;
  std::string name() const;  // "fd", "ags", "ours" or "ideal"
};
// Throws std::invalid_argument naming `flag` and the value.
ExploreMethod ParseExploreMethod(const std::string& name, const std::string& flag);

struct ExploreOptions {
  std::string world;            // world folder or a map_server MAP.yaml
  std::optional<Pose2d> start;  // "world"; overrides the world's start
  std::string method = "ours";  // fd | ags | ours | ideal; overrides the config's utility.method
  double duration_s = 1800.0;   // simulated seconds at most
  uint64_t seed = 1;            // the simulator's seed (overrides sim.seed)
  std::string config_file;      // "" = built-in defaults
  double progress_period_s = 10.0;  // simulated seconds between progress reports; 0 = none
};

// One progress report (also what the progress line prints).
struct ExploreProgress {
  double sim_s = 0.0;
  double wall_s = 0.0;
  double coverage = 0.0;
  int keyframes = 0;
  int loop_closures = 0;
  int frontiers = 0;
  int64_t goal_id = -1;  // -1: no goal
  Point2d goal_m;        // "map"
  int goals_reached = 0;
  int goals_failed = 0;
  int64_t collisions = 0;
  std::string state;     // waiting | exploring | done
  std::string restarts;  // process mode: "slam 1, nav 2", the processes restarted; "" if none
};

struct CoverageSample {
  double t_s = 0.0;
  double coverage = 0.0;
};

// The paper's "uncertainty evolution" (Fig. 3): mean D-optimality of the
// pose graph's edges; NaN while the graph has no edge.
struct UncertaintySample {
  double t_s = 0.0;
  double mean_edge_d_opt = 0.0;
};

// CPU seconds per hosted node of an in-process run: each algorithm node's
// message handlers, the simulator's ticks and handlers, evaluation (the
// runner's listener, samples and final metrics), and `other` (the rest of the
// process: the bus's dispatch, loading). The six add up to the process's CPU.
struct NodeCpu {
  double sim_s = 0.0;
  double slam_s = 0.0;
  double frontier_s = 0.0;
  double utility_s = 0.0;
  double nav_s = 0.0;
  double evaluation_s = 0.0;
  double other_s = 0.0;
  double total_s() const {
    return sim_s + slam_s + frontier_s + utility_s + nav_s + evaluation_s + other_s;
  }
};

// The cost of a run so far, every 10 simulated seconds and at the end (cost.csv).
struct CostSample {
  double t_s = 0.0;     // simulated
  double wall_s = 0.0;  // since the run started
  NodeCpu cpu;          // cumulative
};

// Throws std::invalid_argument naming --duration and its value unless it is a finite number
// of simulated seconds > 0: inf would never end a run, NaN would end it at once.
void CheckDuration(double duration_s);

// Simulated seconds per CPU second between the first sample at or after
// `from_s` and the last at or before `to_s`; nullopt when they do not span time.
std::optional<double> SimSecondsPerCpuSecond(const std::vector<CostSample>& cost, double from_s,
                                             double to_s);

// What metrics.json holds.
struct RunMetrics {
  std::string world;
  std::string method;
  uint64_t seed = 0;
  double sim_seconds = 0.0;
  double wall_seconds = 0.0;
  double coverage = 0.0;    // docs/architecture.md §6, of the final SLAM map
  double ate_rmse_m = 0.0;  // keyframes vs SIM_TRUTH
  double ate_max_m = 0.0;
  int ate_matched = 0;
  int keyframes = 0;
  int loop_closures = 0;  // loop-closure edges in the final graph
  int64_t collisions = 0;
  int goals_reached = 0;
  int goals_failed = 0;
  int decisions = 0;
  // goals.csv counted: goals by outcome name (every outcome, in GoalOutcome order), and the
  // failed and unreachable ones by reason category, most frequent first.
  std::vector<std::pair<std::string, int>> goal_outcomes;
  std::vector<std::pair<std::string, int>> goal_failures_by_reason;
  // Stuck while exploring (eval/stuck_detector.h), and for how long in all.
  std::vector<StuckEpisode> stuck_episodes;
  double stuck_s = 0.0;
  bool done = false;  // EXPLORE_STATUS said done
  // done | stopped (EXPLORE_CONTROL) | duration | interrupted; process mode also process-failed (a
  // process ended and procman will not bring it back) and procman-exited (the deputy ended before
  // the run did)
  std::string end_reason;
  std::optional<double> time_to_90_coverage_s;  // first sample at >= 0.9
  double free_area_m2 = 0.0;                    // ground-truth free area
  double occupied_precision = 0.0;  // map agreement of the final map (trajectory_metrics.h)
  double free_precision = 0.0;
  // docs/architecture.md §6 of the final graph and map (eval/graph_metrics.h, eval/map_metrics.h).
  double average_degree = 0.0;
  double algebraic_connectivity = 0.0;
  double normalized_tree_connectivity = 0.0;
  double ssim = 0.0;
  double map_rmse = 0.0;
  // Table II over the run's uncertainty timeline.
  double mean_edge_d_opt = 0.0;  // of the final graph
  double d_opt_max = 0.0;
  double d_opt_min = 0.0;
  double d_opt_difference = 0.0;
  double d_opt_reduction_percent = 0.0;
  Pose2d map_in_world;  // where the SLAM map lies in the world (for plots over the truth)
  // Devices in the loop only: how the drivers' scan stamps sit against truth (scan_timing.h).
  std::optional<ScanTiming> scan_timing;
  // In-process runs only (process mode has process_stats.json): CPU per node, and
  // simulated seconds per CPU second over the whole run and, in runs of 600 s or
  // more, its first and last 300 s (wall-clock figures: not deterministic).
  std::optional<NodeCpu> node_cpu;
  std::optional<double> sim_per_cpu;
  std::optional<double> sim_per_cpu_first_300s;
  std::optional<double> sim_per_cpu_last_300s;
  // Process mode only: each supervised process's restarts and how it last ended on its own
  // (metrics.json "processes"; empty in process).
  std::vector<ProcessHistory> processes;
};

struct ExploreResult {
  RunMetrics metrics;
  std::vector<CoverageSample> coverage;           // one per simulated second, then the final map's
  std::vector<UncertaintySample> uncertainty;     // same times as `coverage`
  std::vector<CostSample> cost;                   // in-process runs only
  std::vector<GoalRecord> goals;                  // every goal, in the order chosen (goals.csv)
  OccupancyGrid map;                              // final SLAM map, "map" (empty if none)
  PoseGraph graph;                                // final pose graph, "map"
  std::vector<Pose2d> slam_path;                  // SLAM_POSE re-anchored to the final graph, "map"
  std::vector<std::vector<Point2d>> frontiers_m;  // remaining frontiers' cell centres, "map"
  Pose2d map_in_world;                            // true pose of the first keyframe
};

// Runs one exploration. `stop` (may be null) ends the run early, as Ctrl-C;
// `on_progress` is called every progress_period_s simulated seconds and at
// the end. Throws std::runtime_error / std::invalid_argument for a bad
// world, start, method or config.
ExploreResult RunExploreInProcess(
    const ExploreOptions& options, const std::atomic<bool>* stop = nullptr,
    const std::function<void(const ExploreProgress&)>& on_progress = {});

}  // namespace aslam
