#pragma once

// What an exploration runner hears on the bus, in either hosting: the
// simulator's truth and collisions (for evaluation only: docs/architecture.md §3), the
// SLAM graph, pose and map, the frontiers, and the utility's status and goal;
// and what both runners compute from it at the end.

#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "common/lcm_util.h"
#include "common/occupancy_grid.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "common/world_file.h"
#include "eval/explore_runner.h"
#include "eval/goal_ledger.h"
#include "eval/stuck_detector.h"
#include "eval/trajectory_metrics.h"
#include "frontier/frontier.h"

namespace aslam {

class RunListener {
 public:
  // truth_on_host_clock: SIM_TRUTH is stamped on the host's clock (devices in the loop), so
  // only SIM_STATUS tells the simulated time; the drivers' scans are kept to judge their
  // stamps (RunMetrics::scan_timing).
  RunListener(lcm::LCM& lcm, const OccupancyGrid& truth_map, bool truth_on_host_clock = false);

  // The SLAM map placed in the world by the true pose of the first keyframe.
  std::optional<Pose2d> MapInWorld();
  MapAgreement Agreement(const OccupancyGrid& map);
  // Coverage of the newest SLAM_MAP, evaluated when asked rather than for
  // every map: it costs a pass over both grids.
  double coverage();
  // Mean edge D-optimality of the newest POSE_GRAPH (NaN without edges), evaluated when asked.
  double mean_edge_d_opt();
  // SLAM_POSE re-anchored to `graph`'s keyframes.
  std::vector<Pose2d> Path(const PoseGraph& graph) const;
  ExploreProgress Progress(double sim_s, double wall_s);
  // The last report of a run: the final graph's and map's figures.
  ExploreProgress FinalProgress(const RunMetrics& metrics, double sim_s, double wall_s);

  const Subscriptions& subscriptions() const { return subscriptions_; }
  bool heard_sim() const { return heard_sim_; }
  int64_t sim_utime() const { return sim_utime_; }
  const std::vector<TimedPose>& truth() const { return truth_; }
  // Devices in the loop: every third LIDAR_SCAN from the driver, to judge its stamps by truth.
  const std::vector<LidarScan>& scans() const { return scans_; }
  const PoseGraph& graph() const { return graph_; }
  const std::optional<OccupancyGrid>& map() const { return map_; }
  const FrontierList& frontiers() const { return frontiers_; }
  const std::optional<explore_status_t>& status() const { return status_; }
  // Every goal so far (EXPLORE_GOAL, NAV_STATUS, FRONTIERS, UTILITY_SCORES, true distance).
  const GoalLedger& goals() const { return goals_; }
  // Stuck while exploring, by the true pose and EXPLORE_STATUS.
  const StuckDetector& stuck() const { return stuck_; }
  int loop_closures() const { return loop_closures_; }
  int64_t collisions() const { return collisions_; }
  bool done() const { return done_; }
  // Ended by EXPLORE_CONTROL (stop, or return home on request).
  bool stopped() const { return stopped_; }

 private:
  struct PathPoint {
    int node = 0;
    Pose2d offset;  // SLAM pose in the frame of keyframe `node`
  };
  void Heard(int64_t utime);
  double sim_s() const { return sim_utime_ * 1e-6; }

  const OccupancyGrid& truth_map_;
  bool truth_on_host_clock_;
  Subscriptions subscriptions_;
  bool heard_sim_ = false;
  int64_t sim_utime_ = 0;
  std::vector<TimedPose> truth_;
  std::vector<LidarScan> scans_;
  int64_t scans_heard_ = 0;
  std::optional<Pose2d> map_in_world_;
  std::optional<CoverageEvaluator> coverage_evaluator_;  // once map_in_world_ is known
  PoseGraph graph_;
  std::vector<PathPoint> path_;
  std::optional<OccupancyGrid> map_;
  bool coverage_stale_ = false;
  double coverage_ = 0.0;
  bool d_opt_stale_ = false;
  double mean_edge_d_opt_ = 0.0;
  FrontierList frontiers_;
  std::optional<explore_status_t> status_;
  std::optional<explore_goal_t> goal_;
  GoalLedger goals_;
  StuckDetector stuck_;
  int loop_closures_ = 0;
  int64_t collisions_ = 0;
  bool done_ = false;
  bool stopped_ = false;
};

// The start pose of a run: --start if given (it must lie on a free cell),
// else the world's. Throws std::invalid_argument naming the problem.
Pose2d ResolveStart(const WorldInfo& world, const ExploreOptions& options);

// Fills what both hostings compute alike from the final `result->map` and
// `result->graph`: the final coverage sample, path, frontiers and the metrics
// of map, graph and time (not collisions, goals or the end reason).
void FinishResult(RunListener& listener, const WorldInfo& world, const ExploreOptions& options,
                  const std::string& method, double sim_s, double wall_s, ExploreResult* result);

}  // namespace aslam
