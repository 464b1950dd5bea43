#pragma once

// The exploration state machine (docs/architecture.md §9): when a decision is due, goal ids,
// the blacklist of reached and failed targets, re-sending a goal the navigator missed,
// cancelling a goal nothing replaces, the done timeout, the counters and the status; and
// the user's requests (EXPLORE_CONTROL): pause, resume, stop, return to the start.
// On value types: no LCM and no clock; time is the utimes of the inputs.
//
// Every On* call returns the actions to carry out, in this order:
//   goal      publish EXPLORE_GOAL (a new goal, a re-send or a cancel);
//   decision  run GoalSelector::Decide on map(), pose(), graph(), frontiers() and
//             blacklist_m(), publish its UTILITY_SCORES under the request's id and
//             utime, then carry out OnDecision(decision) before the next input;
//   status    publish EXPLORE_STATUS.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "common/stream_clock.h"
#include "frontier/frontier.h"
#include "navigation/navigator.h"
#include "utility/goal_selector.h"

namespace aslam {

struct ExplorationOptions {
  UtilityMethod method = UtilityMethod::kOurs;  // ags and ours wait for a pose graph
  // No eligible frontier for this long (message time) and the status says done.
  double done_timeout_s = 10.0;
  // When done, drive back to the exploration's start first; the status says done once there
  // (or once the way back has failed kReturnHomeAttempts times).
  bool return_home = false;
  // When the active goal's frontier vanishes, drive on to its target if it is still reachable
  // (DecisionRequest::vanished_goal_target_m) instead of deciding again at once.
  bool keep_vanished_goal = false;

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

enum class ExploreState { kWaiting, kExploring, kDone, kPaused, kReturning, kStopped };
const char* ExploreStateName(ExploreState state);

// An EXPLORE_CONTROL request.
enum class ExploreCommand { kPause, kResume, kStop, kReturnHome };
const char* ExploreCommandName(ExploreCommand command);  // "pause", ..., "return_home"
std::optional<ExploreCommand> ParseExploreCommand(const std::string& name);

// Tries at driving home before the exploration ends without getting there.
inline constexpr int kReturnHomeAttempts = 3;

// What EXPLORE_STATUS carries.
struct ExploreStatus {
  int64_t utime = 0;
  ExploreState state = ExploreState::kWaiting;
  UtilityMethod method = UtilityMethod::kOurs;
  int64_t current_goal_id = -1;
  int num_frontiers = 0;
  int num_eligible = 0;
  int decisions = 0;
  int goals_reached = 0;
  int goals_failed = 0;
  std::string detail;
};

// An EXPLORE_GOAL: go to target_m, or (cancel) stop pursuing goal_id.
struct ExploreGoal {
  int64_t utime = 0;
  int64_t goal_id = 0;
  bool cancel = false;
  Point2d target_m;      // "map"; (0, 0) for a cancel
  int frontier_id = -1;  // -1 for a cancel
};

// A decision to make now; its UTILITY_SCORES carry this id and utime.
struct DecisionRequest {
  int64_t utime = 0;
  int64_t decision_id = 0;
  // keep_vanished_goal: the active goal's frontier vanished. If this target is still
  // reachable, call OnGoalKept() and decide nothing; else decide as usual.
  std::optional<Point2d> vanished_goal_target_m;
};

// What to publish, in member order (see the top of this file).
struct ExploreActions {
  std::optional<ExploreGoal> goal;
  std::optional<DecisionRequest> decision;
  std::optional<ExploreStatus> status;
};

// Where the user's requests have put the exploration.
enum class ControlMode {
  kExploring,  // as the frontiers say (waiting, exploring or done)
  kPaused,
  kReturning,  // driving to the start
  kEnded       // stopped by request, or done after returning home
};

// What an exploration has done so far, kept across a restart of the utility process:
// the counters, the next goal id (so a new goal never reuses one the navigator knows),
// the blacklist, the start, and the user's requests (a paused robot stays paused).
struct ExplorationRecord {
  int decisions = 0;
  int goals_reached = 0;
  int goals_failed = 0;
  int64_t next_goal_id = 0;
  std::vector<Point2d> blacklist_m;
  std::vector<Point2d> retried_m;  // blacklist points forgiven once (ForgiveBlacklist)
  std::optional<Point2d> home_m;   // the first SLAM_POSE ("map"); none before it
  ControlMode mode = ControlMode::kExploring;
  bool paused_while_returning = false;  // what RESUME goes back to
  bool ends_done = false;  // kReturning, kEnded: done (return_home) rather than stopped
  std::string end_detail;  // kEnded: why, as EXPLORE_STATUS says it
  bool operator==(const ExplorationRecord& other) const;
};

class ExplorationManager {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit ExplorationManager(ExplorationOptions options);

  // The latest accepted inputs (SLAM_MAP, SLAM_POSE, POSE_GRAPH, FRONTIERS, NAV_STATUS).
  ExploreActions OnMap(OccupancyGrid map, int64_t utime);
  ExploreActions OnPose(const StampedPose& pose);
  ExploreActions OnGraph(PoseGraph graph, int64_t utime);
  ExploreActions OnFrontiers(FrontierList frontiers);
  ExploreActions OnNavStatus(const NavStatus& status);
  // An EXPLORE_CONTROL request, acted on at the latest input's time (a request's own stamp
  // may come from another clock). A request that does not apply (resume while exploring,
  // anything but return_home once ended) changes nothing; the status says the state.
  ExploreActions OnControl(ExploreCommand command);
  // The GoalSelector's answer to the pending DecisionRequest.
  ExploreActions OnDecision(const GoalDecision& decision);
  // The answer to a DecisionRequest with a vanished goal target that is still reachable:
  // the goal stays; no decision is counted.
  ExploreActions OnGoalKept();

  // Map, pose and frontiers known and, for ags and ours, a pose graph with nodes.
  bool Ready() const;
  // The inputs of a decision; map(), pose() and frontiers() only once Ready().
  const OccupancyGrid& map() const { return *map_; }
  const StampedPose& pose() const { return *pose_; }
  const PoseGraph& graph() const { return graph_; }  // empty before the first
  const std::vector<Frontier>& frontiers() const { return frontiers_->frontiers; }
  // Targets of reached and failed goals ("map"), but for those forgiven.
  const std::vector<Point2d>& blacklist_m() const { return blacklist_m_; }
  // Blacklist points forgiven so far; never shrinks.
  const std::vector<Point2d>& retried_m() const { return retried_m_; }
  // Before the exploration is done with reachable frontiers left, their blacklist points
  // (indices into blacklist_m(), GoalSelector::PointsToRetry) are forgiven once: moved to
  // retried_m(). Call it before OnDecision.
  void ForgiveBlacklist(const std::vector<std::size_t>& indices);
  // Where the exploration started: the first SLAM_POSE ("map"), where return home drives to.
  const std::optional<Point2d>& home_m() const { return home_m_; }
  ControlMode mode() const { return mode_; }

  ExplorationRecord record() const;
  // Continues the counters, goal ids and blacklist of an earlier run (before any input).
  // Throws std::invalid_argument for negative counts or a non-finite blacklist point.
  void Restore(const ExplorationRecord& record);

  int decisions() const { return decisions_; }
  int goals_reached() const { return goals_reached_; }
  int goals_failed() const { return goals_failed_; }
  // -1 when no goal is being pursued (a goal home included).
  int64_t current_goal_id() const { return goal_ ? goal_->goal_id : -1; }
  // The status as of the latest input (published at decisions and at 1 Hz of message time).
  ExploreStatus status() const;

 private:
  struct ActiveGoal {
    int64_t goal_id = 0;
    int frontier_id = -1;
    Point2d target_m;
    int64_t published_utime = 0;
    bool frontier_vanished = false;  // kept on (keep_vanished_goal) after its frontier went
    bool pocket = false;             // chosen nearest first among pockets: never kept on
  };

  // After every accepted input: takes in its time, then Next().
  ExploreActions AfterInput(int64_t utime);
  // The pending decision if Ready, else the status heartbeat; with return_home, the goal
  // home once the exploration is complete.
  ExploreActions Next();
  // With return_home and the exploration complete: the goal home (ending done).
  std::optional<ExploreGoal> ReturnIfComplete();
  // No eligible frontier for done_timeout_s while exploring.
  bool ExplorationComplete() const;
  // Returning: a goal to home_m_ (known) with a new id.
  std::optional<ExploreGoal> GoHome();
  void End(bool done, std::string detail);
  // The cancel of the active goal, which is then dropped (not counted, not blacklisted).
  std::optional<ExploreGoal> CancelGoal();
  std::string MissingInputs() const;
  // The active goal as EXPLORE_GOAL, stamped now.
  ExploreGoal PublishGoal();
  ExploreStatus PublishStatus();

  const ExplorationOptions options_;

  std::optional<OccupancyGrid> map_;
  std::optional<StampedPose> pose_;
  PoseGraph graph_;
  std::optional<FrontierList> frontiers_;

  int64_t latest_utime_ = 0;  // the exploration's clock: the latest in-line input's utime
  // Inputs come from several channels, slightly out of order, and may be far apart in tests
  // and replays; a stamp far off (a bad clock) must neither end the exploration early
  // (done timer) nor freeze the heartbeat, and a real clock step is followed.
  StreamClock clock_{60'000'000, kDefaultResyncMessages, /*late_tolerance_us=*/60'000'000};
  std::optional<int64_t> last_status_utime_;
  bool decision_pending_ = true;              // no goal yet: decide as soon as the inputs allow
  bool vanished_goal_check_pending_ = false;  // keep_vanished_goal: is its target reachable?

  std::optional<ActiveGoal> goal_;
  int64_t next_goal_id_ = 0;
  std::vector<Point2d> blacklist_m_;
  std::vector<Point2d> retried_m_;
  std::optional<int64_t> no_eligible_since_utime_;
  int last_num_eligible_ = 0;
  int decisions_ = 0;
  int goals_reached_ = 0;
  int goals_failed_ = 0;

  std::optional<Point2d> home_m_;
  ControlMode mode_ = ControlMode::kExploring;
  bool paused_while_returning_ = false;
  bool ends_done_ = false;  // as ExplorationRecord::ends_done
  int return_attempts_ = 0;
  std::string end_detail_;
};

}  // namespace aslam
