#pragma once

// The navigator in closed loop with the simulator, in-process on memq://
// (docs/architecture.md §4), for tests and the goal-reaching benchmark. Stands in for SLAM:
// SIM_TRUTH is relayed as SLAM_POSE (frame "map" = "world") and the world's
// true map is published once as SLAM_MAP. Never use this outside tests and
// benchmarks: no algorithm may see SIM_TRUTH.

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "common/occupancy_grid.h"
#include "drivers/sim/sim_node.h"
#include "drivers/sim/simulator.h"
#include "navigation/costmap.h"
#include "navigation/nav_config.h"
#include "navigation/nav_node.h"
#include "navigation/navigator.h"

namespace aslam {

class NavClosedLoop {
 public:
  // Throws std::invalid_argument for a start the simulator rejects.
  NavClosedLoop(const OccupancyGrid& world_map, const Pose2d& start, const NavOptions& nav_options,
                const SimulatorOptions& sim_options = {});

  // Publishes EXPLORE_GOAL (a goal or a cancel) at the current time.
  void SendGoal(int64_t goal_id, Point2d goal_m);
  void SendCancel(int64_t goal_id);

  // Ticks until `done` (checked after each dispatch) or `seconds` of
  // simulated time pass; returns whether `done` held.
  bool RunUntil(const std::function<bool()>& done, double seconds);
  // Until the latest NAV_STATUS for `goal_id` is terminal (not active).
  bool RunUntilSettled(int64_t goal_id, double seconds);

  lcm::LCM& lcm() { return host_.lcm(); }
  InProcessHost& host() { return host_; }
  const Simulator& simulator() const { return simulator_; }
  const NavNode& nav() const { return *nav_node_; }
  // The latest NAV_STATUS heard on the bus.
  const std::optional<NavStatus>& last_status() const { return last_status_; }
  int64_t utime() const { return simulator_.utime(); }
  double distance_traveled_m() const { return distance_traveled_m_; }
  int64_t nav_paths_heard() const { return nav_paths_heard_; }
  // Smallest gap seen between the robot's disc and a wall (true pose,
  // cell-resolution distance field, so good to about half a cell).
  double min_clearance_m() const { return min_clearance_m_; }

 private:
  InProcessHost host_;
  Simulator simulator_;
  std::unique_ptr<SimNode> sim_node_;
  std::unique_ptr<NavNode> nav_node_;
  Subscriptions harness_;
  std::optional<NavStatus> last_status_;
  std::optional<Pose2d> last_truth_;
  double distance_traveled_m_ = 0.0;
  Costmap world_costmap_;  // for its obstacle distances only
  double min_clearance_m_ = std::numeric_limits<double>::infinity();
  int64_t nav_paths_heard_ = 0;
};

struct GoalRunResult {
  NavState state = NavState::kActive;  // kActive: still running at the timeout
  std::string detail;
  double time_s = 0.0;  // simulated, goal sent to terminal state
  double distance_traveled_m = 0.0;
  double final_distance_to_goal_m = 0.0;
  int64_t collisions = 0;
  int recoveries_used = 0;
  double min_clearance_m = 0.0;  // NavClosedLoop::min_clearance_m
};

// One goal from `start`, run until a terminal state or `timeout_s`.
GoalRunResult RunGoal(const OccupancyGrid& world_map, const Pose2d& start, Point2d goal_m,
                      const NavOptions& nav_options, const SimulatorOptions& sim_options,
                      double timeout_s);

}  // namespace aslam
