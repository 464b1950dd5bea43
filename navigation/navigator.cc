#include "navigation/navigator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/text_format.h"

namespace aslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int64_t kMicrosecondsPerSecond = 1'000'000;
// When the plans' goal-distance field is recomputed (see Replan).
constexpr int64_t kGoalDistancesRenewUs = 30'000'000;
constexpr std::size_t kFieldWeakSettledCells = 20'000;

double Distance(Point2d a, Point2d b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }
Point2d Position(const Pose2d& pose) { return {pose.x_m, pose.y_m}; }
int64_t Micros(double seconds) { return static_cast<int64_t>(std::llround(seconds * 1e6)); }

}  // namespace

const char* NavStateName(NavState state) {
  switch (state) {
    case NavState::kIdle: return "idle";
    case NavState::kActive: return "active";
    case NavState::kReached: return "reached";
    case NavState::kFailed: return "failed";
    case NavState::kUnreachable: return "unreachable";
  }
  return "?";
}

const char* RecoveryPhaseName(RecoveryPhase phase) {
  switch (phase) {
    case RecoveryPhase::kNone: return "none";
    case RecoveryPhase::kRotate: return "rotate";
    case RecoveryPhase::kBackOff: return "back_off";
  }
  return "?";
}

namespace {
DwaOptions SqueezeDwaOptions(const NavOptions& options) {
  DwaOptions squeeze = options.dwa;
  squeeze.safety_margin_m = std::min(squeeze.safety_margin_m, options.navigator.squeeze_margin_m);
  return squeeze;
}
}  // namespace

Navigator::Navigator(NavOptions options)
    : options_(std::move(options)),
      planner_(options_.global_planner),
      dwa_(options_.dwa),
      squeeze_dwa_(SqueezeDwaOptions(options_)) {}

void Navigator::SetMap(const OccupancyGrid& map) {
  map_ = map;
  has_map_ = true;
  costmap_current_ = false;
  UpdateScanMarks();
  if (has_path_ && PathBlocked()) replan_due_ = true;
}

void Navigator::UpdateScanMarks() {
  const double range_m = options_.navigator.scan_mark_range_m;
  std::vector<Point2d> marks;
  if (range_m <= 0.0 || !pose_) {
    kept_marks_m_.clear();
  } else {
    if (marks_cleared_utime_ != scan_utime_) ClearMarksSeenThrough();
    // Every return the map does not already hold as an obstacle, as the DWA's LocalObstacles
    // takes them: a wall's returns a cell off its mapped face narrow a gap for the DWA, so
    // they must for the planner too, or it plans through gaps the DWA will not drive.
    const Point2d robot = Position(pose_->pose);
    // Those that shut the path ahead (a chair in a door, a gap narrower than mapped) are kept
    // for the goal, unless seen through or mapped: the way they shut must stay shut when the
    // robot turns away, or the plan flips back to it. The rest matter only while near: kept,
    // noisy returns would thicken every obstacle by their spread and shut real gaps.
    const double shut_m = options_.costmap.robot_radius_m + options_.costmap.clearance_margin_m +
                          0.5 * map_.resolution_m();
    std::vector<Point2d> ahead;
    for (std::size_t i = path_index_; has_path_ && i < path_m_.size(); ++i) {
      if (Distance(path_m_[i], robot) <= range_m + shut_m) ahead.push_back(path_m_[i]);
    }
    for (const Point2d& p : scan_points_m_) {
      if (Distance(p, robot) > range_m) continue;
      marks.push_back(p);
      const bool shuts_path = std::any_of(
          ahead.begin(), ahead.end(), [&](const Point2d& q) { return Distance(p, q) <= shut_m; });
      marks_shut_path_ = marks_shut_path_ || shuts_path;
      if (shuts_path) kept_marks_m_.push_back(p);
    }
  }
  marks.insert(marks.end(), kept_marks_m_.begin(), kept_marks_m_.end());
  // One mark per cell, none the map holds as an obstacle (nor off it).
  const int threshold = options_.costmap.occupied_threshold;
  auto cells_of = [&](const std::vector<Point2d>& points) {
    std::vector<std::size_t> cells;
    for (const Point2d& p : points) {
      const CellIndex cell = map_.WorldToCell(p);
      if (map_.Contains(cell) && map_.at(cell) < threshold) cells.push_back(map_.LinearIndex(cell));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    return cells;
  };
  const std::vector<std::size_t> kept_cells = cells_of(kept_marks_m_);
  kept_marks_m_.clear();
  for (std::size_t index : kept_cells) {
    kept_marks_m_.push_back(map_.CellCenter(map_.CellOfLinearIndex(index)));
  }
  std::vector<std::size_t> cells = cells_of(marks);
  // Update only when the marks change (or the map did).
  if (costmap_current_ && cells == marked_cells_) return;
  costmap_current_ = true;
  marked_cells_ = std::move(cells);
  marks_utime_ = scan_utime_;
  ++marks_revision_;  // on a new map too: the same indices may be other cells of a grown grid
  OccupancyGrid marked = map_;
  for (std::size_t index : marked_cells_) marked.mutable_cells()[index] = OccupancyGrid::kOccupied;
  // Incremental: recomputes only near the cells that changed since the last
  // costmap (new map cells or marks); costs are those of a fresh Costmap.
  costmap_.Update(marked, options_.costmap);
}

bool Navigator::OnAMappedObstaclesFace(CellIndex cell) const {
  const int threshold = options_.costmap.occupied_threshold;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      if (map_.ValueOr({cell.col + dc, cell.row + dr}, 0) >= threshold) return true;
    }
  }
  return false;
}

void Navigator::ClearMarksSeenThrough() {
  marks_cleared_utime_ = scan_utime_;
  const int num_beams = static_cast<int>(scan_beam_points_.size());
  if (num_beams == 0 || scan_angle_increment_rad_ <= 0.0) return;
  const double half_cell_m = 0.5 * map_.resolution_m();
  const double margin_m = options_.navigator.scan_mark_clear_margin_m;
  const int beams_per_turn =
      std::max(num_beams, static_cast<int>(std::lround(2.0 * M_PI / scan_angle_increment_rad_)));
  // A beam passing within half a cell of the mark's centre, returning beyond the margin.
  auto seen_through = [&](const Point2d& mark, int beam) {
    if (beam < 0 || beam >= num_beams || scan_beam_points_[beam] < 0) return false;
    const Point2d& origin = scan_origins_m_[scan_beam_points_[beam]];
    const Point2d& end = scan_points_m_[scan_beam_points_[beam]];
    const double length_m = Distance(origin, end);
    if (length_m <= 0.0) return false;
    const double ux = (end.x_m - origin.x_m) / length_m, uy = (end.y_m - origin.y_m) / length_m;
    const double dx = mark.x_m - origin.x_m, dy = mark.y_m - origin.y_m;
    const double along_m = dx * ux + dy * uy;
    return along_m > 0.0 && along_m + margin_m < length_m &&
           std::abs(dx * uy - dy * ux) <= half_cell_m;
  };
  // A cell the scan still returns from keeps its mark, whatever beams pass beside the return;
  // so does one on a mapped obstacle's face (the beams that pass it graze the face: the return
  // beyond it is the same obstacle's).
  std::vector<std::size_t> returning;
  for (const Point2d& p : scan_points_m_) {
    const CellIndex cell = map_.WorldToCell(p);
    if (map_.Contains(cell)) returning.push_back(map_.LinearIndex(cell));
  }
  std::sort(returning.begin(), returning.end());
  std::vector<Point2d> kept;
  kept.reserve(kept_marks_m_.size());
  for (const Point2d& mark : kept_marks_m_) {
    const CellIndex cell = map_.WorldToCell(mark);
    if (!map_.Contains(cell) || OnAMappedObstaclesFace(cell) ||
        std::binary_search(returning.begin(), returning.end(), map_.LinearIndex(cell))) {
      kept.push_back(mark);
      continue;
    }
    const double bearing_rad =
        WrapAngle(std::atan2(mark.y_m - scan_sensor_m_.y_m, mark.x_m - scan_sensor_m_.x_m) -
                  scan_sensor_m_.yaw_rad - scan_angle_min_rad_);
    const double from_first = bearing_rad < 0.0 ? bearing_rad + 2.0 * M_PI : bearing_rad;
    const int beam = static_cast<int>(std::lround(from_first / scan_angle_increment_rad_));
    bool cleared = false;
    for (int b : {beam - 1, beam, beam + 1}) {
      // Beam indices go round a full turn (a 360° scan's first beam follows its last).
      cleared = cleared || seen_through(mark, (b + beams_per_turn) % beams_per_turn);
    }
    if (!cleared) kept.push_back(mark);
  }
  kept_marks_m_ = std::move(kept);
}

PlanningObstacles Navigator::planning_obstacles() const {
  PlanningObstacles obstacles;
  obstacles.utime = marks_utime_;
  obstacles.points_m.reserve(marked_cells_.size());
  for (std::size_t index : marked_cells_) {
    obstacles.points_m.push_back(map_.CellCenter(map_.CellOfLinearIndex(index)));
  }
  return obstacles;
}

void Navigator::SetPose(const StampedPose& pose) {
  if (pose_ && status_.state == NavState::kActive) {
    goal_driven_m_ += Distance(Position(pose_->pose), Position(pose.pose));
  }
  pose_ = pose;
  if (!recent_poses_.empty() && pose.utime <= recent_poses_.back().utime) recent_poses_.clear();
  recent_poses_.push_back(pose);
  while (pose.utime - recent_poses_.front().utime > kMicrosecondsPerSecond) {
    recent_poses_.pop_front();
  }
}

Pose2d Navigator::PoseAt(int64_t utime) const {
  const auto after = std::upper_bound(recent_poses_.begin(), recent_poses_.end(), utime,
                                      [](int64_t t, const StampedPose& p) { return t < p.utime; });
  if (after == recent_poses_.begin()) return recent_poses_.front().pose;
  const StampedPose& before = *std::prev(after);
  if (after == recent_poses_.end()) {
    // Newer than the newest pose (the sweep's last beams): go on at its velocities.
    const double dt_s = static_cast<double>(utime - before.utime) / kMicrosecondsPerSecond;
    return before.pose *
           Pose2d{before.linear_velocity_mps * dt_s, 0.0, before.angular_velocity_radps * dt_s};
  }
  const double fraction =
      static_cast<double>(utime - before.utime) / static_cast<double>(after->utime - before.utime);
  return Interpolate(before.pose, after->pose, fraction);
}

void Navigator::SetScan(const LidarScan& scan) {
  scan_points_m_.clear();
  scan_origins_m_.clear();
  scan_beam_points_.assign(scan.range_m.size(), -1);
  scan_utime_ = scan.utime;
  if (!pose_) {
    scan_beam_points_.clear();
    return;
  }
  // An instantaneous scan is placed at the latest pose; a swept one beam by beam.
  const Pose2d sensor_in_map = pose_->pose.Compose(scan.sensor_pose);
  scan_sensor_m_ = sensor_in_map;
  scan_angle_min_rad_ = scan.angle_min_rad;
  scan_angle_increment_rad_ = scan.angle_increment_rad;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    if (!scan.IsValidReturn(i)) continue;
    const double angle_rad = scan.BeamAngle(i);
    const double range_m = scan.range_m[i];
    const Point2d in_sensor{range_m * std::cos(angle_rad), range_m * std::sin(angle_rad)};
    const Pose2d sensor =
        scan.beam_time_s.empty()
            ? sensor_in_map
            : PoseAt(scan.utime + std::llround(scan.beam_time_s[i] * kMicrosecondsPerSecond)) *
                  scan.sensor_pose;
    scan_beam_points_[i] = static_cast<int>(scan_points_m_.size());
    scan_points_m_.push_back(sensor.Transform(in_sensor));
    scan_origins_m_.push_back(Position(sensor));
  }
}

void Navigator::SetGoal(int64_t goal_id, Point2d goal_m, int64_t utime) {
  if (goal_id == status_.goal_id) {
    // Re-sent goals are common (full-state publishers); only a moved goal counts.
    if (Distance(goal_m, status_.goal_m) < 1e-6) return;
  } else {
    status_.recoveries_used = 0;
    squeezing_ = false;
    kept_marks_m_.clear();  // a new goal starts from the latest scan's marks
    first_path_m_ = -1.0;
    goal_driven_m_ = 0.0;
  }
  status_.goal_id = goal_id;
  status_.goal_m = goal_m;
  plan_target_m_ = goal_m;
  status_.state = NavState::kActive;
  status_.recovery = RecoveryPhase::kNone;
  status_.distance_remaining_m = -1.0;
  status_.detail.clear();
  status_.utime = utime;
  ClearPath();
  replan_due_ = true;
  dwa_failures_ = 0;
  aligning_ = false;
  looking_ = false;
  ResetProgress(utime);
}

bool Navigator::Cancel(int64_t goal_id, int64_t utime) {
  if (goal_id != status_.goal_id) return false;
  status_.utime = utime;
  Stop(NavState::kIdle, "cancelled");
  return true;
}

void Navigator::ClearPath() {
  if (has_path_ || !path_m_.empty()) ++path_revision_;
  has_path_ = false;
  path_m_.clear();
  path_suffix_m_.clear();
  path_length_m_ = 0.0;
  path_index_ = 0;
}

void Navigator::Stop(NavState state, const std::string& detail) {
  status_.state = state;
  status_.recovery = RecoveryPhase::kNone;
  looking_ = false;
  status_.detail = detail;
  if (state != NavState::kReached) status_.distance_remaining_m = -1.0;
  ClearPath();
  last_velocity_ = {};
}

void Navigator::RestartClock(int64_t utime) {
  pose_.reset();
  kept_marks_m_.clear();
  replan_due_ = true;
  phase_start_utime_ = utime;
  ResetProgress(utime);
}

void Navigator::ResetProgress(int64_t utime) {
  advance_m_ = 0.0;
  last_remaining_m_ = std::numeric_limits<double>::quiet_NaN();
  last_progress_utime_ = utime;
}

bool Navigator::PathBlocked() const {
  // Cells near the path's start may be inscribed on purpose (the planner's start escape).
  for (std::size_t i = path_index_; i < path_m_.size(); ++i) {
    const bool in_start_escape =
        path_length_m_ - path_suffix_m_[i] <= options_.global_planner.start_escape_m;
    if (!in_start_escape && !costmap_.Traversable(costmap_.WorldToCell(path_m_[i]))) return true;
  }
  return false;
}

bool Navigator::Replan(int64_t utime) {
  ++replans_;
  replan_due_ = false;
  blocked_by_marks_ = false;
  last_plan_utime_ = utime;
  marks_shut_path_ = false;
  if (utime - scan_utime_ <= Micros(options_.navigator.pose_timeout_s)) UpdateScanMarks();
  if (!PlanToGoal(utime)) return false;
  if (first_path_m_ < 0.0) first_path_m_ = path_length_m_;
  // Returns the map does not hold shut the way it planned, and the trip (driven + the way
  // round) has grown far past the goal's first plan: give the goal up (the utility, which plans
  // with the marks, chooses again) rather than tour the building finding one way after another
  // shut as the robot arrives at each.
  const NavigatorOptions& n = options_.navigator;
  const double trip_m = goal_driven_m_ + path_length_m_;
  if (marks_shut_path_ && n.detour_factor > 0.0 &&
      trip_m > n.detour_factor * first_path_m_ + n.detour_slack_m) {
    Stop(NavState::kFailed,
         Format("scan returns the map does not hold shut the way: %.1f m driven and %.1f m "
                "round, against a first plan of %.1f m",
                goal_driven_m_, path_length_m_, first_path_m_));
    return false;
  }
  return true;
}

bool Navigator::PlanToGoal(int64_t utime) {
  const Point2d goal = status_.goal_m;
  const Point2d robot = Position(pose_->pose);
  const CellIndex goal_cell = costmap_.WorldToCell(goal);
  if (!costmap_.Contains(goal_cell)) {
    Stop(NavState::kUnreachable,
         Format("goal (%.2f, %.2f) is outside the map", goal.x_m, goal.y_m));
    return false;
  }
  if (costmap_.Traversable(costmap_.WorldToCell(plan_target_m_)) &&
      PlanTo(costmap_.WorldToCell(plan_target_m_), utime)) {
    return true;
  }
  // The goal (or the cell kept for it) cannot be stood on or got to: approach it at the
  // nearest reachable cell that sees it, and keep that cell while it can be planned to. A goal
  // on an obstacle's face (a frontier a newer scan or map closed) is approached the same way,
  // as the utility does when it chooses one.
  const std::vector<CellIndex> candidates =
      GoalSnapCandidates(costmap_, goal_cell, options_.navigator.goal_snap_m);
  if (candidates.empty() && !costmap_.Traversable(goal_cell)) {
    Stop(NavState::kUnreachable,
         costmap_.cost(goal_cell) >= Costmap::kLethal
             ? Format("goal (%.2f, %.2f) is in an obstacle", goal.x_m, goal.y_m)
             : Format("goal (%.2f, %.2f) is too close to an obstacle for the robot", goal.x_m,
                      goal.y_m));
    return false;
  }
  planner_.Search(costmap_, costmap_.WorldToCell(robot), candidates, &snap_tree_);
  const std::optional<CellIndex> reachable = ReachableGoalCell(snap_tree_, goal_cell, candidates);
  std::optional<GlobalPath> path;
  if (reachable) path = snap_tree_.PathTo(*reachable);
  if (!path || path->points_m.empty()) {
    if (!marked_cells_.empty() && ReachableWithoutMarks(costmap_.WorldToCell(robot), goal_cell)) {
      // Returns the map does not hold shut the way (clutter, or a gap at the edge of what the
      // robot fits): they change as it moves, so look again before giving the goal up.
      blocked_by_marks_ = true;
      ClearPath();
      return false;
    }
    Stop(NavState::kUnreachable,
         Format("no path from (%.2f, %.2f) to goal (%.2f, %.2f) in the costmap", robot.x_m,
                robot.y_m, goal.x_m, goal.y_m));
    return false;
  }
  plan_target_m_ = costmap_.CellCenter(*reachable);
  SetPath(std::move(path->points_m));
  return true;
}

bool Navigator::ReachableWithoutMarks(CellIndex robot_cell, CellIndex goal_cell) {
  unmarked_costmap_.Update(map_, options_.costmap);
  const std::vector<CellIndex> candidates =
      GoalSnapCandidates(unmarked_costmap_, goal_cell, options_.navigator.goal_snap_m);
  if (candidates.empty() && !unmarked_costmap_.Traversable(goal_cell)) return false;
  planner_.Search(unmarked_costmap_, robot_cell, candidates, &snap_tree_);
  return ReachableGoalCell(snap_tree_, goal_cell, candidates).has_value();
}

bool Navigator::PlanTo(CellIndex target_cell, int64_t utime) {
  const Point2d robot = Position(pose_->pose);
  // The goal-distance field is renewed for a new target or grid, when a plan settles three
  // times the cells the first on it did (walls mapped since, or the robot off its extent, have
  // made it weak), and now and then for walls gone since (a plan may then cost a little more).
  const bool field_weak = plan_tree_.settled_count() > kFieldWeakSettledCells &&
                          plan_tree_.settled_count() / 3 > field_first_plan_settled_;
  if (!goal_distances_.SameGrid(costmap_) || goal_distances_.start() != target_cell || field_weak ||
      utime < goal_distances_utime_ || utime - goal_distances_utime_ >= kGoalDistancesRenewUs) {
    planner_.DistancesToGoal(costmap_, target_cell, costmap_.WorldToCell(robot), &goal_distances_);
    goal_distances_utime_ = utime;
    field_first_plan_settled_ = std::numeric_limits<std::size_t>::max();
  }
  std::optional<GlobalPath> path = planner_.Plan(costmap_, robot, costmap_.CellCenter(target_cell),
                                                 &plan_tree_, &goal_distances_);
  field_first_plan_settled_ = std::min(field_first_plan_settled_, plan_tree_.settled_count());
  if (!path || path->points_m.empty()) return false;
  SetPath(std::move(path->points_m));
  return true;
}

void Navigator::SetPath(std::vector<Point2d> points_m) {
  path_m_ = std::move(points_m);
  path_suffix_m_.assign(path_m_.size(), 0.0);
  for (std::size_t i = path_m_.size() - 1; i-- > 0;) {
    path_suffix_m_[i] = path_suffix_m_[i + 1] + Distance(path_m_[i], path_m_[i + 1]);
  }
  path_length_m_ = path_suffix_m_.front();
  path_index_ = 0;
  has_path_ = true;
  ++path_revision_;
  last_remaining_m_ = std::numeric_limits<double>::quiet_NaN();  // the new path starts the count
}

void Navigator::AdvancePathIndex() {
  if (!has_path_) return;
  // Look a bounded stretch ahead only, so a path passing near itself cannot make the index jump.
  const Point2d robot = Position(pose_->pose);
  const double window_m = options_.navigator.path_lookahead_m + 1.0;
  double best_m = Distance(robot, path_m_[path_index_]);
  std::size_t best = path_index_;
  for (std::size_t i = path_index_ + 1; i < path_m_.size(); ++i) {
    if (path_suffix_m_[path_index_] - path_suffix_m_[i] > window_m) break;
    const double d = Distance(robot, path_m_[i]);
    if (d < best_m) {
      best_m = d;
      best = i;
    }
  }
  path_index_ = best;
}

double Navigator::DistanceRemainingM() const {
  if (!has_path_) return -1.0;
  return path_suffix_m_[path_index_] + Distance(Position(pose_->pose), path_m_[path_index_]);
}

std::vector<Point2d> Navigator::PathAhead() const {
  std::vector<Point2d> ahead;
  for (std::size_t i = path_index_; i < path_m_.size(); ++i) {
    ahead.push_back(path_m_[i]);
    if (path_suffix_m_[path_index_] - path_suffix_m_[i] >= options_.navigator.path_lookahead_m)
      break;
  }
  return ahead;
}

double Navigator::PathHeadingRad() const {
  const Point2d robot = Position(pose_->pose);
  Point2d toward = status_.goal_m;
  if (has_path_) {
    // About a metre along the path: far enough to see past the cell the robot is on.
    toward = path_m_.back();
    for (std::size_t i = path_index_; i < path_m_.size(); ++i) {
      if (path_suffix_m_[path_index_] - path_suffix_m_[i] >= 1.0) {
        toward = path_m_[i];
        break;
      }
    }
  }
  if (Distance(robot, toward) < 1e-6) return pose_->pose.yaw_rad;
  return std::atan2(toward.y_m - robot.y_m, toward.x_m - robot.x_m);
}

bool Navigator::RearClear(const LocalObstacles& obstacles) const {
  const Pose2d& pose = pose_->pose;
  const double current_m = obstacles.ClearanceM(Position(pose));
  // Safe, or at least moving away from whatever the robot is pressed against.
  const double needed_m = std::min(
      options_.costmap.robot_radius_m + options_.navigator.recovery.rear_clearance_margin_m,
      current_m + 0.005);
  for (double s = 0.05; s <= 0.151; s += 0.05) {
    const Point2d p{pose.x_m - s * std::cos(pose.yaw_rad), pose.y_m - s * std::sin(pose.yaw_rad)};
    if (obstacles.ClearanceM(p) < needed_m) return false;
  }
  return true;
}

double Navigator::ChooseBackOffHeading(const LocalObstacles& obstacles) const {
  const Pose2d& pose = pose_->pose;
  const Point2d robot = Position(pose);
  const RecoveryOptions& r = options_.navigator.recovery;
  const double current_m = obstacles.ClearanceM(robot);
  const double needed_m =
      std::min(options_.costmap.robot_radius_m + r.rear_clearance_margin_m, current_m + 0.005);
  const double back_off_m = std::max(r.back_off_distance_m, 0.05);
  const double path_heading_rad = PathHeadingRad();
  constexpr int kHeadings = 16;
  double best_score = -kInf;
  double best_yaw_rad = pose.yaw_rad;
  for (int k = 0; k < kHeadings; ++k) {
    const double turn_rad = WrapAngle(k * 2.0 * M_PI / kHeadings);
    const double yaw_rad = WrapAngle(pose.yaw_rad + turn_rad);
    const Point2d back{-std::cos(yaw_rad), -std::sin(yaw_rad)};
    bool feasible = true;
    for (double s = 0.05; s <= back_off_m + 1e-9 && feasible; s += 0.05) {
      feasible =
          obstacles.ClearanceM({robot.x_m + s * back.x_m, robot.y_m + s * back.y_m}) >= needed_m;
    }
    if (!feasible) continue;
    const Point2d end{robot.x_m + back_off_m * back.x_m, robot.y_m + back_off_m * back.y_m};
    // Clearance gained first, then facing the path after backing off, then a short turn.
    const double score = std::min(obstacles.ClearanceM(end), 1.0) +
                         0.3 * std::cos(WrapAngle(yaw_rad - path_heading_rad)) -
                         0.05 * std::abs(turn_rad) / M_PI;
    if (score > best_score) {
      best_score = score;
      best_yaw_rad = yaw_rad;
    }
  }
  return best_yaw_rad;
}

void Navigator::StartRecovery(int64_t utime, const std::string& reason,
                              const LocalObstacles& obstacles, bool look) {
  const NavigatorOptions& n = options_.navigator;
  if (status_.recoveries_used >= n.max_recoveries) {
    Stop(NavState::kFailed,
         reason + " after " + std::to_string(status_.recoveries_used) + " recoveries");
    return;
  }
  ++status_.recoveries_used;
  aligning_ = false;
  squeezing_ = squeezing_ || !look;
  status_.recovery = RecoveryPhase::kRotate;
  recovery_reason_ = reason;
  status_.detail = "recovering: " + reason;
  phase_start_utime_ = utime;
  looking_ = look;
  // A look judges the way by what it sees now: the kept marks shut it, so they start afresh.
  if (look) kept_marks_m_.clear();
  rotate_target_yaw_rad_ =
      look ? WrapAngle(pose_->pose.yaw_rad + M_PI - 0.05) : ChooseBackOffHeading(obstacles);
}

VelocityCommand Navigator::StepRecovery(int64_t utime, const LocalObstacles& obstacles) {
  const RecoveryOptions& r = options_.navigator.recovery;
  const Pose2d& pose = pose_->pose;
  VelocityCommand command;
  command.utime = utime;
  if (status_.recovery == RecoveryPhase::kRotate) {
    const double error_rad = WrapAngle(rotate_target_yaw_rad_ - pose.yaw_rad);
    // Turning at most half a turn; the limit covers a base that cannot turn.
    const int64_t limit_us = Micros(M_PI / r.rotate_speed_radps + 3.0);
    if (std::abs(error_rad) > r.rotate_aligned_rad && utime - phase_start_utime_ <= limit_us) {
      // Proportional near the target so the base's angular deceleration does not overshoot.
      const double speed = std::clamp(1.5 * std::abs(error_rad), 0.2, r.rotate_speed_radps);
      command.angular_radps = std::copysign(speed, error_rad);
      return command;
    }
    if (looking_) return EndRecovery(utime, command);  // turned around and still shut: look again
    status_.recovery = RecoveryPhase::kBackOff;
    phase_start_utime_ = utime;
    back_off_start_m_ = Position(pose);
  }
  const int64_t limit_us = Micros(r.back_off_distance_m / r.back_off_speed_mps + 2.0);
  if (Distance(Position(pose), back_off_start_m_) < r.back_off_distance_m &&
      utime - phase_start_utime_ <= limit_us && RearClear(obstacles)) {
    command.linear_mps = -r.back_off_speed_mps;
    return command;
  }
  return EndRecovery(utime, command);
}

VelocityCommand Navigator::EndRecovery(int64_t utime, const VelocityCommand& command) {
  // Replan from here and retry.
  status_.recovery = RecoveryPhase::kNone;
  status_.detail.clear();
  looking_ = false;
  replan_due_ = true;
  dwa_failures_ = 0;
  ResetProgress(utime);
  return command;
}

std::optional<VelocityCommand> Navigator::Align(int64_t utime, const LocalObstacles& obstacles) {
  const NavigatorOptions& n = options_.navigator;
  const Pose2d& pose = pose_->pose;
  const double error_rad = WrapAngle(PathHeadingRad() - pose.yaw_rad);
  aligning_ = std::abs(error_rad) > (aligning_ ? n.align_done_rad : n.align_start_rad);
  if (!aligning_) return std::nullopt;
  // Brake straight at the DWA's deceleration, if the little stretch that takes is free.
  const DwaOptions& d = options_.dwa;
  const double v_mps =
      std::max(0.0, last_velocity_.linear_mps - d.max_linear_accel_mps2 * d.control_period_s);
  const double stop_m = v_mps * d.control_period_s + 0.5 * v_mps * v_mps / d.max_linear_accel_mps2;
  for (double s = 0.0; s <= stop_m + 1e-9; s += 0.025) {
    const Point2d p{pose.x_m + s * std::cos(pose.yaw_rad), pose.y_m + s * std::sin(pose.yaw_rad)};
    if (obstacles.ClearanceM(p) < d.robot_radius_m) {
      aligning_ = false;  // the DWA knows how to brake along its arc
      return std::nullopt;
    }
  }
  const double speed_radps = std::clamp(1.5 * std::abs(error_rad), 0.3, n.align_speed_radps);
  return VelocityCommand{utime, v_mps, std::copysign(speed_radps, error_rad)};
}

NavOutput Navigator::Step(int64_t utime) {
  NavOutput out;
  out.command.utime = utime;
  status_.utime = utime;
  const NavigatorOptions& n = options_.navigator;
  auto finish = [&](const VelocityCommand& command) {
    out.command = command;
    out.command.utime = utime;
    last_velocity_ = {command.linear_mps, command.angular_radps};
    out.status = status_;
    return out;
  };
  if (status_.state != NavState::kActive) return finish({});
  if (!has_map_ || !pose_) {
    status_.detail = !has_map_ ? "waiting for a map" : "waiting for a pose";
    return finish({});
  }
  if (utime - pose_->utime > Micros(n.pose_timeout_s)) {
    status_.detail = Format("pose is stale (%.2f s old)", (utime - pose_->utime) * 1e-6);
    return finish({});
  }
  // Inputs are fine (again): the detail says what the navigator is doing.
  status_.detail =
      status_.recovery == RecoveryPhase::kNone ? "" : "recovering: " + recovery_reason_;

  const Point2d robot = Position(pose_->pose);
  if (Distance(robot, status_.goal_m) <= n.goal_tolerance_m ||
      Distance(robot, plan_target_m_) <= n.goal_tolerance_m) {
    const double remaining_m = has_path_ ? DistanceRemainingM() : Distance(robot, status_.goal_m);
    Stop(NavState::kReached, "");
    status_.distance_remaining_m = remaining_m;
    return finish({});
  }

  bool planned = true;
  // A look around replans every cycle (it has no path) and ends at the first plan.
  const bool may_plan = status_.recovery == RecoveryPhase::kNone || looking_;
  if (may_plan &&
      (replan_due_ || !has_path_ || utime - last_plan_utime_ >= Micros(n.replan_period_s))) {
    out.replanned = true;
    planned = Replan(utime);
    if (!planned && !blocked_by_marks_) return finish({});
    if (planned && looking_) EndRecovery(utime, {});
  }
  AdvancePathIndex();
  status_.distance_remaining_m = DistanceRemainingM();

  static const std::vector<Point2d> kNoPoints;
  const bool scan_fresh = utime - scan_utime_ <= Micros(n.pose_timeout_s);
  const LocalObstacles obstacles(map_, scan_fresh ? scan_points_m_ : kNoPoints, pose_->pose,
                                 options_.local_obstacles);
  if (!planned) {
    if (!looking_) {
      StartRecovery(utime, "no path past scan returns the map does not hold", obstacles,
                    /*look=*/true);
      if (status_.state != NavState::kActive) return finish({});
    }
    return finish(StepRecovery(utime, obstacles));
  }

  if (status_.recovery == RecoveryPhase::kNone) {
    const double remaining_m = status_.distance_remaining_m;
    if (!std::isnan(last_remaining_m_)) advance_m_ += last_remaining_m_ - remaining_m;
    last_remaining_m_ = remaining_m;
    if (advance_m_ >= n.progress_margin_m) {
      advance_m_ = 0.0;
      last_progress_utime_ = utime;
    }
    if (utime - last_progress_utime_ > Micros(n.progress_timeout_s)) {
      StartRecovery(utime, Format("no progress for %g s", n.progress_timeout_s), obstacles);
    } else if (const auto turn = Align(utime, obstacles)) {
      return finish(*turn);
    } else {
      last_dwa_ = (squeezing_ ? squeeze_dwa_ : dwa_)
                      .Plan(pose_->pose, last_velocity_, PathAhead(), obstacles);
      const DwaResult& result = last_dwa_;
      if (result.found) {
        dwa_failures_ = 0;
        return finish({utime, result.command.linear_mps, result.command.angular_radps});
      }
      if (++dwa_failures_ < n.dwa_failures_for_recovery) return finish({});
      StartRecovery(utime, "no collision-free trajectory", obstacles);
    }
    if (status_.state != NavState::kActive) return finish({});
  }
  return finish(StepRecovery(utime, obstacles));
}

}  // namespace aslam
