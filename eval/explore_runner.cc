#include "eval/explore_runner.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "common/robot_config.h"
#include "common/types_lcm.h"
#include "common/world_file.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/sim_node.h"
#include "eval/run_listener.h"
#include "eval/trajectory_metrics.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_lcm.h"
#include "frontier/frontier_node.h"
#include "navigation/nav_config.h"
#include "navigation/nav_node.h"
#include "slam/slam_config.h"
#include "slam/slam_node.h"
#include "utility/utility_config.h"
#include "utility/utility_node.h"

namespace aslam {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

ExploreResult RunExploreInProcess(const ExploreOptions& options, const std::atomic<bool>* stop,
                                  const std::function<void(const ExploreProgress&)>& on_progress) {
  const auto method = ParseUtilityMethod(options.method);
  if (!method)
    throw std::invalid_argument("--method '" + options.method + "': expected fd, ags or ours");
  if (!(options.duration_s > 0)) throw std::invalid_argument("--duration must be > 0");

  // Every option is loaded and validated before anything runs (docs/architecture.md §7); the
  // robot once, for the simulator and the navigator, whose planning frontier and
  // utility share.
  const std::string& file = options.config_file;
  const RobotOptions robot = LoadRobotOptionsFromFile(file);
  SimulatorOptions sim_options =
      LoadSimulatorOptions(ConfigReader::FromOptionalFile(file, "sim"), robot);
  sim_options.seed = options.seed;
  const SlamConfig slam_config = LoadSlamConfigFromFile(file);
  const NavOptions nav_options = LoadNavOptions(ConfigReader::FromOptionalFile(file, "nav"), robot);
  const FrontierOptions frontier_options =
      LoadFrontierOptions(ConfigReader::FromOptionalFile(file, "frontier"), nav_options);
  UtilityOptions utility_options =
      LoadUtilityOptions(ConfigReader::FromOptionalFile(file, "utility"), nav_options);
  utility_options.selector.method = *method;

  const WorldInfo world = LoadWorld(options.world);
  const Pose2d start = ResolveStart(world, options);

  Simulator simulator(world.map.grid, start, sim_options);
  InProcessHost host;
  SimNode sim_node(host.lcm(), simulator, {options.world, std::nullopt});
  SlamNode slam_node(host.lcm(), slam_config.slam, slam_config.node);
  FrontierNode frontier_node(host.lcm(), frontier_options);
  UtilityNode utility_node(host.lcm(), utility_options);
  NavNode nav_node(host.lcm(), nav_options);
  RunListener listener(host.lcm(), world.map.grid);

  ExploreResult result;
  const int64_t end_us = std::llround(options.duration_s * 1e6);
  const int64_t progress_us = std::llround(options.progress_period_s * 1e6);
  int64_t next_sample_us = 1'000'000;
  int64_t next_progress_us = progress_us;
  bool interrupted = false;
  const Clock::time_point wall_start = Clock::now();

  auto progress = [&] {
    return listener.Progress(simulator.utime() * 1e-6,
                             std::chrono::duration<double>(Clock::now() - wall_start).count());
  };

  host.Run(
      [&] {
        if (simulator.utime() >= end_us) return false;
        sim_node.Tick();
        return true;
      },
      [&] {
        const int64_t now_us = simulator.utime();
        if (now_us >= next_sample_us) {
          result.coverage.push_back({now_us * 1e-6, listener.coverage()});
          result.uncertainty.push_back({now_us * 1e-6, listener.mean_edge_d_opt()});
          next_sample_us += 1'000'000;
        }
        if (on_progress && progress_us > 0 && now_us >= next_progress_us) {
          on_progress(progress());
          next_progress_us += progress_us;
        }
        if (stop && stop->load()) {
          interrupted = true;
          return false;
        }
        return !listener.done();
      });
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();

  // The final state straight from SLAM: newer than its last (rate-limited) SLAM_MAP.
  result.map = slam_node.slam().RenderMap();
  result.graph = slam_node.slam().graph();
  const double sim_s = simulator.utime() * 1e-6;
  FinishResult(listener, world, options, UtilityMethodName(*method), sim_s, wall_s, &result);
  RunMetrics& m = result.metrics;
  m.collisions = simulator.collisions();
  m.goals_reached = utility_node.goals_reached();
  m.goals_failed = utility_node.goals_failed();
  m.decisions = utility_node.decisions();
  m.done = listener.done();
  m.end_reason = m.done ? "done" : interrupted ? "interrupted" : "duration";
  if (on_progress) on_progress(listener.FinalProgress(m, sim_s, wall_s));
  return result;
}

}  // namespace aslam
