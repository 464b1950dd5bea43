#include "utility/exploration_manager.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "common/text_format.h"

namespace aslam {
namespace {

constexpr int64_t kStatusPeriodUs = 1'000'000;
// The navigator reporting an older goal this long after ours went out: it
// missed EXPLORE_GOAL (a dropped UDP message), so send it again.
constexpr int64_t kGoalResendUs = 1'000'000;

int64_t SecondsToUs(double s) { return static_cast<int64_t>(s * 1e6); }

}  // namespace

void ExplorationOptions::Validate() const {
  if (!std::isfinite(done_timeout_s) || done_timeout_s < 0.0) {
    throw std::invalid_argument(Format("done_timeout_s must be >= 0, got %g", done_timeout_s));
  }
}

const char* ExploreStateName(ExploreState state) {
  switch (state) {
    case ExploreState::kWaiting: return "waiting";
    case ExploreState::kExploring: return "exploring";
    case ExploreState::kDone: return "done";
    case ExploreState::kPaused: return "paused";
    case ExploreState::kReturning: return "returning";
    case ExploreState::kStopped: return "stopped";
  }
  return "?";
}

const char* ExploreCommandName(ExploreCommand command) {
  switch (command) {
    case ExploreCommand::kPause: return "pause";
    case ExploreCommand::kResume: return "resume";
    case ExploreCommand::kStop: return "stop";
    case ExploreCommand::kReturnHome: return "return_home";
  }
  return "?";
}

std::optional<ExploreCommand> ParseExploreCommand(const std::string& name) {
  for (const ExploreCommand command : {ExploreCommand::kPause, ExploreCommand::kResume,
                                       ExploreCommand::kStop, ExploreCommand::kReturnHome}) {
    if (name == ExploreCommandName(command)) return command;
  }
  return std::nullopt;
}

ExplorationManager::ExplorationManager(ExplorationOptions options) : options_(options) {
  options_.Validate();
}

ExploreActions ExplorationManager::OnMap(OccupancyGrid map, int64_t utime) {
  map_ = std::move(map);
  return AfterInput(utime);
}

ExploreActions ExplorationManager::OnPose(const StampedPose& pose) {
  pose_ = pose;
  if (!home_m_) home_m_ = Point2d{pose.pose.x_m, pose.pose.y_m};
  return AfterInput(pose.utime);
}

ExploreActions ExplorationManager::OnGraph(PoseGraph graph, int64_t utime) {
  graph_ = std::move(graph);
  return AfterInput(utime);
}

ExploreActions ExplorationManager::OnFrontiers(FrontierList frontiers) {
  const int64_t utime = frontiers.utime;
  frontiers_ = std::move(frontiers);
  if (!goal_) {
    decision_pending_ = true;  // new frontiers may hold an eligible one
  } else {
    const std::vector<Frontier>& fs = frontiers_->frontiers;
    const int goal_frontier_id = goal_->frontier_id;
    const bool still_there =
        std::any_of(fs.begin(), fs.end(),
                    [goal_frontier_id](const Frontier& f) { return f.id == goal_frontier_id; });
    if (!still_there && !goal_->frontier_vanished) {
      goal_->frontier_vanished = true;
      (options_.keep_vanished_goal && !goal_->pocket ? vanished_goal_check_pending_
                                                     : decision_pending_) = true;
    }
  }
  return AfterInput(utime);
}

ExploreActions ExplorationManager::OnNavStatus(const NavStatus& status) {
  // Goal ids stay unique across a restart of the utility: continue after the navigator's.
  if (status.goal_id < std::numeric_limits<int64_t>::max()) {
    next_goal_id_ = std::max(next_goal_id_, status.goal_id + 1);
  }
  // Stamped before this report's time is taken in, as the node always has.
  std::optional<ExploreGoal> goal;
  if (goal_ && status.goal_id == goal_->goal_id) {
    const bool reached = status.state == NavState::kReached;
    const bool failed = status.state == NavState::kFailed || status.state == NavState::kUnreachable;
    if ((reached || failed) && mode_ == ControlMode::kReturning) {
      const Point2d home = goal_->target_m;
      goal_.reset();
      if (reached) {
        End(ends_done_, Format("returned to the start (%.2f, %.2f)", home.x_m, home.y_m));
      } else if (++return_attempts_ >= kReturnHomeAttempts) {
        End(ends_done_,
            Format("could not return to the start in %d attempts: ", kReturnHomeAttempts) +
                status.detail);
      } else {
        goal = GoHome();
      }
    } else if (reached || failed) {
      (reached ? goals_reached_ : goals_failed_) += 1;
      blacklist_m_.push_back(goal_->target_m);
      goal_.reset();
      decision_pending_ = true;
    }
  } else if (goal_ && status.goal_id < goal_->goal_id &&
             status.utime - goal_->published_utime >= kGoalResendUs) {
    goal = PublishGoal();
  }
  ExploreActions actions = AfterInput(status.utime);
  if (goal) actions.goal = goal;
  return actions;
}

ExploreActions ExplorationManager::OnControl(ExploreCommand command) {
  std::optional<ExploreGoal> goal;
  switch (command) {
    case ExploreCommand::kPause:
      if (mode_ == ControlMode::kExploring || mode_ == ControlMode::kReturning) {
        paused_while_returning_ = mode_ == ControlMode::kReturning;
        goal = CancelGoal();
        mode_ = ControlMode::kPaused;
        no_eligible_since_utime_.reset();  // the done timeout starts again after resume
      }
      break;
    case ExploreCommand::kResume:
      if (mode_ == ControlMode::kPaused && paused_while_returning_) {
        goal = GoHome();
      } else if (mode_ == ControlMode::kPaused) {
        mode_ = ControlMode::kExploring;
        decision_pending_ = true;
      }
      break;
    case ExploreCommand::kStop:
      if (mode_ != ControlMode::kEnded) {
        goal = CancelGoal();
        End(/*done=*/false, "stopped by request");
      }
      break;
    case ExploreCommand::kReturnHome:
      if (mode_ != ControlMode::kReturning) {
        // Asked once the exploration is complete, the way home still ends it as done.
        ends_done_ = (mode_ == ControlMode::kEnded && ends_done_) || ExplorationComplete();
        return_attempts_ = 0;
        goal = CancelGoal();
        if (home_m_) {
          goal = GoHome();  // replaces the goal (the navigator follows the newest id)
        } else {
          End(ends_done_, "no pose yet, so the robot is still at the start");
        }
      }
      break;
  }
  ExploreActions actions = Next();
  if (!actions.decision) actions.status = PublishStatus();  // the answer to the request
  if (goal) actions.goal = goal;
  return actions;
}

ExploreActions ExplorationManager::OnDecision(const GoalDecision& decision) {
  ExploreActions actions;
  if (mode_ != ControlMode::kExploring) {  // not asked for since a request: nothing to act on
    actions.status = PublishStatus();
    return actions;
  }
  ++decisions_;
  last_num_eligible_ = decision.num_eligible;
  if (decision.has_goal()) {
    const FrontierScore& chosen = decision.chosen();
    goal_ =
        ActiveGoal{next_goal_id_++, chosen.frontier_id, chosen.target_m, 0, false, chosen.pocket};
    no_eligible_since_utime_.reset();
    actions.goal = PublishGoal();
  } else {
    // The goal's frontier is gone and nothing replaces it: stop the navigator.
    const std::optional<ExploreGoal> cancel = CancelGoal();
    if (!no_eligible_since_utime_) no_eligible_since_utime_ = latest_utime_;
    const std::optional<ExploreGoal> home = ReturnIfComplete();  // replaces the cancelled goal
    actions.goal = home ? home : cancel;
  }
  actions.status = PublishStatus();
  return actions;
}

ExploreActions ExplorationManager::OnGoalKept() {
  ExploreActions actions;
  actions.status = PublishStatus();
  return actions;
}

void ExplorationManager::ForgiveBlacklist(const std::vector<std::size_t>& indices) {
  std::vector<Point2d> kept;
  for (std::size_t i = 0; i < blacklist_m_.size(); ++i) {
    const bool forgiven = std::find(indices.begin(), indices.end(), i) != indices.end();
    (forgiven ? retried_m_ : kept).push_back(blacklist_m_[i]);
  }
  blacklist_m_ = std::move(kept);
}

namespace {
bool SamePoints(const std::vector<Point2d>& a, const std::vector<Point2d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].x_m != b[i].x_m || a[i].y_m != b[i].y_m) return false;
  }
  return true;
}
}  // namespace

bool ExplorationRecord::operator==(const ExplorationRecord& o) const {
  if (decisions != o.decisions || goals_reached != o.goals_reached ||
      goals_failed != o.goals_failed || next_goal_id != o.next_goal_id ||
      !SamePoints(blacklist_m, o.blacklist_m) || !SamePoints(retried_m, o.retried_m) ||
      home_m.has_value() != o.home_m.has_value() || mode != o.mode ||
      paused_while_returning != o.paused_while_returning || ends_done != o.ends_done ||
      end_detail != o.end_detail) {
    return false;
  }
  return !home_m || (home_m->x_m == o.home_m->x_m && home_m->y_m == o.home_m->y_m);
}

ExplorationRecord ExplorationManager::record() const {
  return ExplorationRecord{
      decisions_, goals_reached_, goals_failed_,           next_goal_id_, blacklist_m_, retried_m_,
      home_m_,    mode_,          paused_while_returning_, ends_done_,    end_detail_};
}

void ExplorationManager::Restore(const ExplorationRecord& record) {
  if (record.decisions < 0 || record.goals_reached < 0 || record.goals_failed < 0 ||
      record.next_goal_id < 0) {
    throw std::invalid_argument("exploration record: counts and goal ids must be >= 0");
  }
  for (const auto* points : {&record.blacklist_m, &record.retried_m}) {
    for (const Point2d& p : *points) {
      if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m)) {
        throw std::invalid_argument("exploration record: a blacklist point is not finite");
      }
    }
  }
  if (record.home_m && (!std::isfinite(record.home_m->x_m) || !std::isfinite(record.home_m->y_m))) {
    throw std::invalid_argument("exploration record: the home point is not finite");
  }
  if ((record.mode == ControlMode::kReturning || record.paused_while_returning) && !record.home_m) {
    throw std::invalid_argument("exploration record: the way home without a home point");
  }
  decisions_ = record.decisions;
  goals_reached_ = record.goals_reached;
  goals_failed_ = record.goals_failed;
  next_goal_id_ = record.next_goal_id;
  blacklist_m_ = record.blacklist_m;
  retried_m_ = record.retried_m;
  home_m_ = record.home_m;
  mode_ = record.mode;
  paused_while_returning_ = record.paused_while_returning;
  ends_done_ = record.ends_done;
  end_detail_ = record.end_detail;
}

ExploreActions ExplorationManager::AfterInput(int64_t utime) {
  if (clock_.Offer(utime) == StreamClock::Verdict::kResynced) {
    // The clock stepped: the timers restart from the new time.
    last_status_utime_.reset();
    if (no_eligible_since_utime_) no_eligible_since_utime_ = clock_.now_utime();
    if (goal_) goal_->published_utime = clock_.now_utime();
  }
  latest_utime_ = clock_.now_utime();
  return Next();
}

ExploreActions ExplorationManager::Next() {
  ExploreActions actions;
  const bool check_vanished_goal = vanished_goal_check_pending_ && goal_ && !decision_pending_;
  if (mode_ == ControlMode::kExploring && (decision_pending_ || check_vanished_goal) && Ready()) {
    // The decision's own status goes out with OnDecision, so no heartbeat is due after it.
    decision_pending_ = false;
    vanished_goal_check_pending_ = false;
    actions.decision = DecisionRequest{latest_utime_, decisions_, std::nullopt};
    if (check_vanished_goal) actions.decision->vanished_goal_target_m = goal_->target_m;
    return actions;
  }
  actions.goal = ReturnIfComplete();
  // Returning without a goal: restored from the state file after a restart.
  if (!actions.goal && mode_ == ControlMode::kReturning && !goal_) actions.goal = GoHome();
  if (actions.goal || !last_status_utime_ ||
      latest_utime_ - *last_status_utime_ >= kStatusPeriodUs) {
    actions.status = PublishStatus();
  }
  return actions;
}

std::optional<ExploreGoal> ExplorationManager::ReturnIfComplete() {
  if (!options_.return_home || !ExplorationComplete()) return std::nullopt;
  ends_done_ = true;
  return_attempts_ = 0;
  return GoHome();
}

bool ExplorationManager::ExplorationComplete() const {
  return mode_ == ControlMode::kExploring && Ready() && !goal_ && no_eligible_since_utime_ &&
         latest_utime_ - *no_eligible_since_utime_ >= SecondsToUs(options_.done_timeout_s);
}

std::optional<ExploreGoal> ExplorationManager::GoHome() {
  mode_ = ControlMode::kReturning;
  goal_ = ActiveGoal{next_goal_id_++, /*frontier_id=*/-1, *home_m_, 0};
  return PublishGoal();
}

void ExplorationManager::End(bool done, std::string detail) {
  mode_ = ControlMode::kEnded;
  ends_done_ = done;
  end_detail_ = std::move(detail);
  goal_.reset();
}

std::optional<ExploreGoal> ExplorationManager::CancelGoal() {
  if (!goal_) return std::nullopt;
  const ExploreGoal cancel{latest_utime_, goal_->goal_id, /*cancel=*/true, {}, -1};
  goal_.reset();
  return cancel;
}

bool ExplorationManager::Ready() const {
  const bool graph_known = !graph_.nodes.empty();
  return map_ && pose_ && frontiers_ && (graph_known || !MethodUsesGraph(options_.method));
}

std::string ExplorationManager::MissingInputs() const {
  std::string missing;
  auto add = [&missing](const char* name) {
    missing += (missing.empty() ? "" : ", ") + std::string(name);
  };
  if (!map_) add("SLAM_MAP");
  if (!pose_) add("SLAM_POSE");
  if (MethodUsesGraph(options_.method) && graph_.nodes.empty()) add("POSE_GRAPH");
  if (!frontiers_) add("FRONTIERS");
  return missing;
}

ExploreGoal ExplorationManager::PublishGoal() {
  goal_->published_utime = latest_utime_;
  return ExploreGoal{latest_utime_, goal_->goal_id, /*cancel=*/false, goal_->target_m,
                     goal_->frontier_id};
}

ExploreStatus ExplorationManager::PublishStatus() {
  last_status_utime_ = latest_utime_;
  return status();
}

ExploreStatus ExplorationManager::status() const {
  ExploreStatus s;
  s.utime = latest_utime_;
  s.method = options_.method;
  s.current_goal_id = current_goal_id();
  s.num_frontiers = frontiers_ ? static_cast<int>(frontiers_->frontiers.size()) : 0;
  s.num_eligible = last_num_eligible_;
  s.decisions = decisions_;
  s.goals_reached = goals_reached_;
  s.goals_failed = goals_failed_;
  if (mode_ == ControlMode::kPaused) {
    s.state = ExploreState::kPaused;
    s.detail = paused_while_returning_ ? "paused on the way to the start" : "paused";
  } else if (mode_ == ControlMode::kReturning) {
    s.state = ExploreState::kReturning;
    s.detail = Format("returning to the start (%.2f, %.2f), attempt %d of %d", home_m_->x_m,
                      home_m_->y_m, return_attempts_ + 1, kReturnHomeAttempts);
  } else if (mode_ == ControlMode::kEnded) {
    s.state = ends_done_ ? ExploreState::kDone : ExploreState::kStopped;
    s.detail = end_detail_;
  } else if (!Ready()) {
    s.state = ExploreState::kWaiting;
    s.detail = "waiting for " + MissingInputs();
  } else if (goal_) {
    s.state = ExploreState::kExploring;
    s.detail = "goal " + std::to_string(goal_->goal_id) + " to frontier " +
               std::to_string(goal_->frontier_id) +
               Format(" at (%.2f, %.2f)", goal_->target_m.x_m, goal_->target_m.y_m);
  } else if (no_eligible_since_utime_) {
    const int64_t idle_us = latest_utime_ - *no_eligible_since_utime_;
    s.state = ExplorationComplete() ? ExploreState::kDone : ExploreState::kExploring;
    s.detail = Format("no eligible frontier for %.1f s", idle_us * 1e-6);
  } else {
    s.state = ExploreState::kExploring;
    s.detail = "deciding";
  }
  return s;
}

}  // namespace aslam
