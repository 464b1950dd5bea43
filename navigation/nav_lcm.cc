#include "navigation/nav_lcm.h"

#include <cmath>

namespace aslam {

std::optional<NavGoalRequest> FromLcm(const explore_goal_t& msg) {
  if (msg.goal_id < 0) return std::nullopt;
  if (!msg.cancel && (!std::isfinite(msg.x_m) || !std::isfinite(msg.y_m))) return std::nullopt;
  return NavGoalRequest{msg.utime, msg.goal_id, msg.cancel != 0, {msg.x_m, msg.y_m}};
}

explore_goal_t ToLcm(const NavGoalRequest& request) {
  explore_goal_t msg{};
  msg.utime = request.utime;
  msg.goal_id = request.goal_id;
  msg.cancel = request.cancel;
  msg.x_m = request.goal_m.x_m;
  msg.y_m = request.goal_m.y_m;
  msg.frontier_id = -1;
  return msg;
}

nav_status_t ToLcm(const NavStatus& status) {
  nav_status_t msg{};
  msg.utime = status.utime;
  msg.goal_id = status.goal_id;
  switch (status.state) {
    case NavState::kIdle: msg.state = nav_status_t::STATE_IDLE; break;
    case NavState::kActive: msg.state = nav_status_t::STATE_ACTIVE; break;
    case NavState::kReached: msg.state = nav_status_t::STATE_REACHED; break;
    case NavState::kFailed: msg.state = nav_status_t::STATE_FAILED; break;
    case NavState::kUnreachable: msg.state = nav_status_t::STATE_UNREACHABLE; break;
  }
  switch (status.recovery) {
    case RecoveryPhase::kNone: msg.recovery = nav_status_t::RECOVERY_NONE; break;
    case RecoveryPhase::kRotate: msg.recovery = nav_status_t::RECOVERY_ROTATE; break;
    case RecoveryPhase::kBackOff: msg.recovery = nav_status_t::RECOVERY_BACK_OFF; break;
  }
  msg.goal_x_m = status.goal_m.x_m;
  msg.goal_y_m = status.goal_m.y_m;
  msg.distance_remaining_m = status.distance_remaining_m;
  msg.detail = status.detail;
  return msg;
}

std::optional<NavStatus> FromLcm(const nav_status_t& msg) {
  if (msg.goal_id < -1) return std::nullopt;  // -1 = no goal yet; ids are never negative
  NavStatus status;
  status.utime = msg.utime;
  status.goal_id = msg.goal_id;
  switch (msg.state) {
    case nav_status_t::STATE_IDLE: status.state = NavState::kIdle; break;
    case nav_status_t::STATE_ACTIVE: status.state = NavState::kActive; break;
    case nav_status_t::STATE_REACHED: status.state = NavState::kReached; break;
    case nav_status_t::STATE_FAILED: status.state = NavState::kFailed; break;
    case nav_status_t::STATE_UNREACHABLE: status.state = NavState::kUnreachable; break;
    default: return std::nullopt;
  }
  switch (msg.recovery) {
    case nav_status_t::RECOVERY_NONE: status.recovery = RecoveryPhase::kNone; break;
    case nav_status_t::RECOVERY_ROTATE: status.recovery = RecoveryPhase::kRotate; break;
    case nav_status_t::RECOVERY_BACK_OFF: status.recovery = RecoveryPhase::kBackOff; break;
    default: return std::nullopt;
  }
  if (!std::isfinite(msg.goal_x_m) || !std::isfinite(msg.goal_y_m) ||
      !std::isfinite(msg.distance_remaining_m)) {
    return std::nullopt;
  }
  status.goal_m = {msg.goal_x_m, msg.goal_y_m};
  status.distance_remaining_m = msg.distance_remaining_m;
  status.detail = msg.detail;
  return status;
}

namespace {

// Fills a message's num_points, x_m and y_m (floats) from `points_m`.
template <typename Msg>
void SetPoints(const std::vector<Point2d>& points_m, Msg* msg) {
  msg->num_points = static_cast<int32_t>(points_m.size());
  msg->x_m.reserve(points_m.size());
  msg->y_m.reserve(points_m.size());
  for (const Point2d& p : points_m) {
    msg->x_m.push_back(static_cast<float>(p.x_m));
    msg->y_m.push_back(static_cast<float>(p.y_m));
  }
}

}  // namespace

nav_path_t PathToLcm(int64_t utime, int64_t goal_id, const std::vector<Point2d>& path_m,
                     double length_m) {
  nav_path_t msg{};
  msg.utime = utime;
  msg.goal_id = goal_id;
  msg.length_m = length_m;
  SetPoints(path_m, &msg);
  return msg;
}

nav_obstacles_t ToLcm(const PlanningObstacles& obstacles) {
  nav_obstacles_t msg{};
  msg.utime = obstacles.utime;
  SetPoints(obstacles.points_m, &msg);
  return msg;
}

std::optional<PlanningObstacles> FromLcm(const nav_obstacles_t& msg) {
  if (msg.num_points < 0 || msg.x_m.size() != static_cast<std::size_t>(msg.num_points) ||
      msg.y_m.size() != msg.x_m.size()) {
    return std::nullopt;
  }
  PlanningObstacles obstacles;
  obstacles.utime = msg.utime;
  obstacles.points_m.reserve(msg.x_m.size());
  for (std::size_t i = 0; i < msg.x_m.size(); ++i) {
    if (!std::isfinite(msg.x_m[i]) || !std::isfinite(msg.y_m[i])) return std::nullopt;
    obstacles.points_m.push_back({msg.x_m[i], msg.y_m[i]});
  }
  return obstacles;
}

}  // namespace aslam
