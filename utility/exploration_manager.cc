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
  }
  return "?";
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
    if (!still_there) decision_pending_ = true;
  }
  return AfterInput(utime);
}

ExploreActions ExplorationManager::OnNavStatus(const NavStatus& status) {
  // Goal ids stay unique across a restart of the utility: continue after the navigator's.
  if (status.goal_id < std::numeric_limits<int64_t>::max()) {
    next_goal_id_ = std::max(next_goal_id_, status.goal_id + 1);
  }
  std::optional<ExploreGoal> resend;
  if (goal_ && status.goal_id == goal_->goal_id) {
    const bool reached = status.state == NavState::kReached;
    const bool failed = status.state == NavState::kFailed || status.state == NavState::kUnreachable;
    if (reached || failed) {
      (reached ? goals_reached_ : goals_failed_) += 1;
      blacklist_m_.push_back(goal_->target_m);
      goal_.reset();
      decision_pending_ = true;
    }
  } else if (goal_ && status.goal_id < goal_->goal_id &&
             status.utime - goal_->published_utime >= kGoalResendUs) {
    // Stamped before this report's time is taken in, as the node always has.
    resend = PublishGoal();
  }
  ExploreActions actions = AfterInput(status.utime);
  actions.goal = resend;
  return actions;
}

ExploreActions ExplorationManager::OnDecision(const GoalDecision& decision) {
  ++decisions_;
  last_num_eligible_ = decision.num_eligible;
  ExploreActions actions;
  if (decision.has_goal()) {
    const FrontierScore& chosen = decision.chosen();
    goal_ = ActiveGoal{next_goal_id_++, chosen.frontier_id, chosen.target_m, 0};
    no_eligible_since_utime_.reset();
    actions.goal = PublishGoal();
  } else {
    if (goal_) {
      // The goal's frontier is gone and nothing replaces it: stop the navigator.
      actions.goal = ExploreGoal{latest_utime_, goal_->goal_id, /*cancel=*/true, {}, -1};
      goal_.reset();
    }
    if (!no_eligible_since_utime_) no_eligible_since_utime_ = latest_utime_;
  }
  actions.status = PublishStatus();
  return actions;
}

bool ExplorationRecord::operator==(const ExplorationRecord& o) const {
  if (decisions != o.decisions || goals_reached != o.goals_reached ||
      goals_failed != o.goals_failed || next_goal_id != o.next_goal_id ||
      blacklist_m.size() != o.blacklist_m.size()) {
    return false;
  }
  for (std::size_t i = 0; i < blacklist_m.size(); ++i) {
    if (blacklist_m[i].x_m != o.blacklist_m[i].x_m || blacklist_m[i].y_m != o.blacklist_m[i].y_m) {
      return false;
    }
  }
  return true;
}

ExplorationRecord ExplorationManager::record() const {
  return ExplorationRecord{decisions_, goals_reached_, goals_failed_, next_goal_id_, blacklist_m_};
}

void ExplorationManager::Restore(const ExplorationRecord& record) {
  if (record.decisions < 0 || record.goals_reached < 0 || record.goals_failed < 0 ||
      record.next_goal_id < 0) {
    throw std::invalid_argument("exploration record: counts and goal ids must be >= 0");
  }
  for (const Point2d& p : record.blacklist_m) {
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m)) {
      throw std::invalid_argument("exploration record: a blacklist point is not finite");
    }
  }
  decisions_ = record.decisions;
  goals_reached_ = record.goals_reached;
  goals_failed_ = record.goals_failed;
  next_goal_id_ = record.next_goal_id;
  blacklist_m_ = record.blacklist_m;
}

ExploreActions ExplorationManager::AfterInput(int64_t utime) {
  if (clock_.Offer(utime) == StreamClock::Verdict::kResynced) {
    // The clock stepped: the timers restart from the new time.
    last_status_utime_.reset();
    if (no_eligible_since_utime_) no_eligible_since_utime_ = clock_.now_utime();
    if (goal_) goal_->published_utime = clock_.now_utime();
  }
  latest_utime_ = clock_.now_utime();
  ExploreActions actions;
  if (decision_pending_ && Ready()) {
    // The decision's own status goes out with OnDecision, so no heartbeat is due after it.
    decision_pending_ = false;
    actions.decision = DecisionRequest{latest_utime_, decisions_};
  } else if (!last_status_utime_ || latest_utime_ - *last_status_utime_ >= kStatusPeriodUs) {
    actions.status = PublishStatus();
  }
  return actions;
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
  if (!Ready()) {
    s.state = ExploreState::kWaiting;
    s.detail = "waiting for " + MissingInputs();
  } else if (goal_) {
    s.state = ExploreState::kExploring;
    s.detail = "goal " + std::to_string(goal_->goal_id) + " to frontier " +
               std::to_string(goal_->frontier_id) +
               Format(" at (%.2f, %.2f)", goal_->target_m.x_m, goal_->target_m.y_m);
  } else if (no_eligible_since_utime_) {
    const int64_t idle_us = latest_utime_ - *no_eligible_since_utime_;
    s.state = idle_us >= SecondsToUs(options_.done_timeout_s) ? ExploreState::kDone
                                                              : ExploreState::kExploring;
    s.detail = Format("no eligible frontier for %.1f s", idle_us * 1e-6);
  } else {
    s.state = ExploreState::kExploring;
    s.detail = "deciding";
  }
  return s;
}

}  // namespace aslam
