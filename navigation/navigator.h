#pragma once

// The navigator: goal handling, global replanning, DWA path following and
// recovery, as one state machine over the latest map, pose and scan. No LCM
// and no wall clock: time comes from the utimes of the inputs and of Step().
//
//   SetGoal -> active --(within goal_tolerance_m)--> reached
//                |  (facing far off the path: stop and turn toward it first)
//                |  (a goal it cannot stand on: the nearest reachable cell that sees it)
//                |  \--(nowhere to see the goal from / no path)--> unreachable
//                |   (no path only past scan returns the map does not hold: first a look
//                |   around, a half turn in place replanning every cycle, counted as a recovery)
//                |--(no progress for progress_timeout_s, or the DWA finds
//                |   no admissible trajectory several cycles running)-->
//                |   recovery: rotate (to the heading that backing off
//                |   gains most clearance from, preferring the path's
//                |   direction), back off (reverse slowly while the rear is
//                |   clear), replan, resume; once max_recoveries are spent --> failed;
//                |   after such a recovery the DWA keeps squeeze_margin_m, not the robot's
//                |   clearance margin, for the rest of the goal
//   Cancel -> idle
//
// Global plans (A*) are redone every replan_period_s and at once when a
// new map makes a cell of the path untraversable; the planning costmap is the
// map plus the scan returns near the robot that the map does not explain.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "navigation/costmap.h"
#include "navigation/dwa_planner.h"
#include "navigation/global_planner.h"
#include "navigation/local_obstacles.h"
#include "navigation/nav_config.h"

namespace aslam {

enum class NavState { kIdle, kActive, kReached, kFailed, kUnreachable };
enum class RecoveryPhase { kNone, kRotate, kBackOff };

const char* NavStateName(NavState state);
const char* RecoveryPhaseName(RecoveryPhase phase);

struct NavStatus {
  int64_t utime = 0;
  int64_t goal_id = -1;  // -1 before the first goal
  NavState state = NavState::kIdle;
  RecoveryPhase recovery = RecoveryPhase::kNone;
  Point2d goal_m;                      // "map"
  double distance_remaining_m = -1.0;  // along the global path; -1 without one
  int recoveries_used = 0;             // for the current goal
  std::string detail;                  // why: failed, unreachable, waiting, stale pose
};

// An EXPLORE_GOAL: go to goal_m, or stop pursuing goal_id.
struct NavGoalRequest {
  int64_t utime = 0;
  int64_t goal_id = 0;
  bool cancel = false;
  Point2d goal_m;  // "map"
};

// What one control cycle produced.
struct NavOutput {
  VelocityCommand command;  // utime = the Step's utime
  NavStatus status;
  bool replanned = false;  // a global plan was attempted this cycle
};

class Navigator {
 public:
  explicit Navigator(NavOptions options);

  // Rebuilds the planning costmap; a path cell that became untraversable forces a
  // replan on the next Step.
  void SetMap(const OccupancyGrid& map);
  // The robot in "map".
  void SetPose(const StampedPose& pose);
  // Keeps the scan's valid end points (and the sensor at each) in "map", placed with the
  // latest pose; the next replan marks the near ones into its costmap and clears earlier
  // marks its beams pass through.
  void SetScan(const LidarScan& scan);
  // A new goal id starts a new goal; the current id with another point moves
  // the goal (replan, recovery budget kept); the same id and point is a no-op.
  void SetGoal(int64_t goal_id, Point2d goal_m, int64_t utime);
  // Stops and idles if `goal_id` is the current goal; returns whether it was.
  bool Cancel(int64_t goal_id, int64_t utime);

  // The scans' clock stepped (a host clock reset): timers restart from `utime`, and the
  // pose, stamped on the old clock, is forgotten until one on the new clock arrives.
  void RestartClock(int64_t utime);

  // One control cycle at `utime` (the scan rate): replans when due, checks
  // goal and progress, runs the DWA or the recovery, returns the command.
  NavOutput Step(int64_t utime);

  const NavStatus& status() const { return status_; }
  // The current global path ("map"); empty when there is none.
  const std::vector<Point2d>& path_m() const { return path_m_; }
  double path_length_m() const { return path_length_m_; }
  // Increases whenever path_m() is replaced (every replan) or cleared.
  int64_t path_revision() const { return path_revision_; }
  bool has_map() const { return has_map_; }
  const Costmap& costmap() const { return costmap_; }
  const std::vector<Point2d>& scan_points_m() const { return scan_points_m_; }
  // The scan returns marked into the planning costmap (NAV_OBSTACLES), stamped with their scan.
  PlanningObstacles planning_obstacles() const;
  // Increases whenever the marks are recomputed to something new, and with every map.
  int64_t marks_revision() const { return marks_revision_; }
  const NavOptions& options() const { return options_; }
  int64_t replans() const { return replans_; }
  // The latest DWA result (for viewers, tests and tracing).
  const DwaResult& last_dwa() const { return last_dwa_; }

 private:
  void Stop(NavState state, const std::string& detail);
  // false: no path; the state says unreachable or failed (a trip past scan marks too long),
  // or blocked_by_marks_ is set (still active).
  bool Replan(int64_t utime);
  bool PlanToGoal(int64_t utime);  // Replan's search, after the marks are up to date
  // Whether the goal could be reached on the map alone, without the scan marks.
  bool ReachableWithoutMarks(CellIndex robot_cell, CellIndex goal_cell);
  bool PlanTo(CellIndex target_cell, int64_t utime);  // A* to the cell; false: no path
  void SetPath(std::vector<Point2d> points_m);
  bool PathBlocked() const;
  void AdvancePathIndex();
  double DistanceRemainingM() const;
  std::vector<Point2d> PathAhead() const;  // the DWA's view of the path
  double PathHeadingRad() const;           // direction of the path ahead from the robot
  void ClearPath();
  // Marks the scan points within scan_mark_range_m that do not fall on a mapped
  // obstacle cell into the planning costmap (rebuilt only when the marks change). Those that
  // shut the path ahead stay, for the goal, out of reach too, unless the map holds them or a
  // scan sees through them.
  void UpdateScanMarks();
  // Drops the kept marks a beam of the latest scan passes through to a return beyond them.
  void ClearMarksSeenThrough();
  // An 8-neighbour of `cell` is a mapped obstacle.
  bool OnAMappedObstaclesFace(CellIndex cell) const;
  // `look`: a half turn in place that replans every cycle and ends as soon as a plan exists,
  // instead of rotating to back off.
  void StartRecovery(int64_t utime, const std::string& reason, const LocalObstacles& obstacles,
                     bool look = false);
  VelocityCommand StepRecovery(int64_t utime, const LocalObstacles& obstacles);
  // Back to driving: replan now, progress counted from here; returns `command`.
  VelocityCommand EndRecovery(int64_t utime, const VelocityCommand& command);
  double ChooseBackOffHeading(const LocalObstacles& obstacles) const;
  bool RearClear(const LocalObstacles& obstacles) const;
  void ResetProgress(int64_t utime);
  // The turn-in-place command while the heading is far off the path's; nullopt: let the DWA drive.
  std::optional<VelocityCommand> Align(int64_t utime, const LocalObstacles& obstacles);

  NavOptions options_;
  GlobalPlanner planner_;
  ShortestPathTree plan_tree_;  // the last plan's search, its memory reused by the next
  // Distances around walls to the plan target: the plans' A* heuristic (see Replan).
  ShortestPathTree goal_distances_;
  int64_t goal_distances_utime_ = 0;
  std::size_t field_first_plan_settled_ = 0;  // cells the first plan on the field settled
  DwaPlanner dwa_;
  DwaPlanner squeeze_dwa_;  // the DWA with navigator.squeeze_margin_m

  OccupancyGrid map_;
  Costmap costmap_;
  // Marks that shut the path ahead, kept for the goal: cell centres, "map".
  std::vector<Point2d> kept_marks_m_;
  int64_t marks_cleared_utime_ = -1;       // the scan that last cleared them
  std::vector<std::size_t> marked_cells_;  // the latest scan's within reach and the kept, sorted
  int64_t marks_utime_ = 0;                // the scan they came from
  int64_t marks_revision_ = 0;
  bool costmap_current_ = false;   // costmap_ = map_ + marked_cells_
  Costmap unmarked_costmap_;       // map_ alone, brought up to date only when asked
  bool blocked_by_marks_ = false;  // the last replan found the way shut by marks only
  bool marks_shut_path_ = false;   // this replan's marks shut the path it had
  double first_path_m_ = -1.0;     // the goal's first plan; -1 before it
  double goal_driven_m_ = 0.0;     // how far the robot moved while the goal was active
  bool has_map_ = false;
  std::optional<StampedPose> pose_;
  // The last second of poses: a swept scan's beams are placed from the pose at each one's time.
  std::deque<StampedPose> recent_poses_;
  Pose2d PoseAt(int64_t utime) const;
  std::vector<Point2d> scan_points_m_;
  std::vector<Point2d> scan_origins_m_;  // the sensor at each scan point's beam
  std::vector<int> scan_beam_points_;    // per beam: its index in scan_points_m_, -1 if none
  Pose2d scan_sensor_m_;                 // the sensor at the scan's time
  double scan_angle_min_rad_ = 0.0;
  double scan_angle_increment_rad_ = 0.0;
  int64_t scan_utime_ = -1;

  NavStatus status_;
  Point2d plan_target_m_;       // the goal, or the reachable cell that sees it (goal_snap_m)
  ShortestPathTree snap_tree_;  // the search for that cell
  bool has_path_ = false;
  std::vector<Point2d> path_m_;
  std::vector<double> path_suffix_m_;  // length from point i to the end
  double path_length_m_ = 0.0;
  std::size_t path_index_ = 0;  // nearest path point to the robot
  bool replan_due_ = false;
  int64_t last_plan_utime_ = 0;
  int64_t replans_ = 0;
  int64_t path_revision_ = 0;

  // Progress: how far the robot advanced along its paths since it last made progress, net
  // of going back. A replan's jump in the distance remaining (a detour, or plans flipping
  // between two routes) is not the robot moving, so it never counts.
  double advance_m_ = 0.0;
  double last_remaining_m_ = 0.0;  // on the current path at the previous step; NaN after a plan
  int64_t last_progress_utime_ = 0;
  int dwa_failures_ = 0;
  bool aligning_ = false;   // turning in place toward the path before the DWA drives
  bool squeezing_ = false;  // this goal needed a recovery: squeeze_dwa_ drives
  DwaVelocity last_velocity_;
  DwaResult last_dwa_;

  // The running recovery.
  std::string recovery_reason_;
  bool looking_ = false;  // a look around (see StartRecovery)
  int64_t phase_start_utime_ = 0;
  double rotate_target_yaw_rad_ = 0.0;
  Point2d back_off_start_m_;
};

}  // namespace aslam
