#include "eval/nav_closed_loop.h"

#include <algorithm>
#include <cmath>

#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "navigation/nav_lcm.h"

namespace aslam {

NavClosedLoop::NavClosedLoop(const OccupancyGrid& world_map, const Pose2d& start,
                             const NavOptions& nav_options, const SimulatorOptions& sim_options)
    : simulator_(world_map, start, sim_options),
      harness_(host_.lcm()),
      world_costmap_(world_map, CostmapOptions{}) {
  sim_node_ = std::make_unique<SimNode>(host_.lcm(), simulator_, SimNodeOptions{"closed-loop", {}});
  nav_node_ = std::make_unique<NavNode>(host_.lcm(), nav_options);
  // SLAM stand-in: the true pose, relabelled "map" (the two frames coincide here).
  harness_.Add<pose_t>(channels::kSimTruth, [this](const pose_t& truth) {
    pose_t pose = truth;
    pose.frame = "map";
    host_.lcm().publish(channels::kSlamPose, &pose);
    const Pose2d p = FromLcm(truth.pose);
    if (last_truth_)
      distance_traveled_m_ += std::hypot(p.x_m - last_truth_->x_m, p.y_m - last_truth_->y_m);
    last_truth_ = p;
    const double gap_m =
        world_costmap_.ObstacleDistanceM(world_costmap_.WorldToCell({p.x_m, p.y_m})) -
        0.5 * world_costmap_.resolution_m() - simulator_.options().robot.radius_m;
    min_clearance_m_ = std::min(min_clearance_m_, gap_m);
    return true;
  });
  harness_.Add<nav_status_t>(channels::kNavStatus, [this](const nav_status_t& msg) {
    last_status_ = FromLcm(msg);
    return last_status_.has_value();
  });
  harness_.Add<nav_path_t>(channels::kNavPath, [this](const nav_path_t&) {
    ++nav_paths_heard_;
    return true;
  });
  const occupancy_grid_t map = ToLcm(world_map, 0, 1, "map");
  host_.lcm().publish(channels::kSlamMap, &map);
  host_.DispatchPending();
}

void NavClosedLoop::SendGoal(int64_t goal_id, Point2d goal_m) {
  const explore_goal_t msg = ToLcm(NavGoalRequest{utime(), goal_id, false, goal_m});
  host_.lcm().publish(channels::kExploreGoal, &msg);
  host_.DispatchPending();
}

void NavClosedLoop::SendCancel(int64_t goal_id) {
  const explore_goal_t msg = ToLcm(NavGoalRequest{utime(), goal_id, true, {}});
  host_.lcm().publish(channels::kExploreGoal, &msg);
  host_.DispatchPending();
}

bool NavClosedLoop::RunUntil(const std::function<bool()>& done, double seconds) {
  const int64_t end_utime = utime() + static_cast<int64_t>(std::llround(seconds * 1e6));
  bool reached = done();
  host_.Run(
      [&] {
        if (reached || utime() >= end_utime) return false;
        sim_node_->Tick();
        return true;
      },
      [&] {
        reached = done();
        return !reached;
      });
  return reached;
}

bool NavClosedLoop::RunUntilSettled(int64_t goal_id, double seconds) {
  return RunUntil(
      [&] {
        return last_status_ && last_status_->goal_id == goal_id &&
               last_status_->state != NavState::kActive;
      },
      seconds);
}

GoalRunResult RunGoal(const OccupancyGrid& world_map, const Pose2d& start, Point2d goal_m,
                      const NavOptions& nav_options, const SimulatorOptions& sim_options,
                      double timeout_s) {
  NavClosedLoop loop(world_map, start, nav_options, sim_options);
  const int64_t start_utime = loop.utime();
  constexpr int64_t kGoalId = 1;
  loop.SendGoal(kGoalId, goal_m);
  loop.RunUntilSettled(kGoalId, timeout_s);
  GoalRunResult result;
  if (loop.last_status() && loop.last_status()->goal_id == kGoalId) {
    result.state = loop.last_status()->state;
    result.detail = loop.last_status()->detail;
  }
  result.recoveries_used = loop.nav().navigator().status().recoveries_used;
  result.time_s = (loop.utime() - start_utime) * 1e-6;
  result.distance_traveled_m = loop.distance_traveled_m();
  const Pose2d& end = loop.simulator().true_pose();
  result.final_distance_to_goal_m = std::hypot(end.x_m - goal_m.x_m, end.y_m - goal_m.y_m);
  result.collisions = loop.simulator().collisions();
  result.min_clearance_m = loop.min_clearance_m();
  return result;
}

}  // namespace aslam
