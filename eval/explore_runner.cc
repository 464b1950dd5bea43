#include "eval/explore_runner.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "common/channels.h"
#include "common/cpu_time.h"
#include "common/inproc_host.h"
#include "common/lcm_util.h"
#include "common/robot_config.h"
#include "common/text_format.h"
#include "common/types_lcm.h"
#include "common/world_file.h"
#include "drivers/sim/sim_config.h"
#include "drivers/sim/sim_node.h"
#include "eval/ideal_mapper_node.h"
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

constexpr int64_t kCostPeriodUs = 10'000'000;
constexpr double kRateWindowS = 300.0;

}  // namespace

std::string ExploreMethod::name() const { return ideal ? "ideal" : UtilityMethodName(utility); }

ExploreMethod ParseExploreMethod(const std::string& name, const std::string& flag) {
  if (name == "ideal") return {UtilityMethod::kFd, true};
  const auto utility = ParseUtilityMethod(name);
  if (!utility)
    throw std::invalid_argument(flag + " '" + name + "': expected fd, ags, ours or ideal");
  return {*utility, false};
}

void CheckDuration(double duration_s) {
  if (std::isfinite(duration_s) && duration_s > 0) return;
  throw std::invalid_argument("--duration " + Format("%g", duration_s) +
                              ": expected a finite number of simulated seconds > 0");
}

std::optional<double> SimSecondsPerCpuSecond(const std::vector<CostSample>& cost, double from_s,
                                             double to_s) {
  const CostSample* first = nullptr;
  const CostSample* last = nullptr;
  for (const CostSample& sample : cost) {
    if (first == nullptr && sample.t_s >= from_s) first = &sample;
    if (sample.t_s <= to_s) last = &sample;
  }
  if (first == nullptr || last == nullptr || last->t_s <= first->t_s) return std::nullopt;
  const double cpu_s = last->cpu.total_s() - first->cpu.total_s();
  if (!(cpu_s > 0)) return std::nullopt;
  return (last->t_s - first->t_s) / cpu_s;
}

ExploreResult RunExploreInProcess(const ExploreOptions& options, const std::atomic<bool>* stop,
                                  const std::function<void(const ExploreProgress&)>& on_progress) {
  const ExploreMethod method = ParseExploreMethod(options.method, "--method");
  CheckDuration(options.duration_s);

  // One thread: every node's CPU is charged on this thread (OpenCV's workers
  // would go uncounted), and bench jobs already fill the cores.
  cv::setNumThreads(0);
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
  utility_options.selector.method = method.utility;

  const WorldInfo world = LoadWorld(options.world);
  const Pose2d start = ResolveStart(world, options);

  Simulator simulator(world.map.grid, start, sim_options);
  InProcessHost host;
  SimNode sim_node(host.lcm(), simulator, {options.world, std::nullopt});
  SlamNodeOptions slam_node_options = slam_config.node;
  // memq loses nothing, and compressing and inflating every map would cost the run time.
  slam_node_options.map_encoding = SlamNodeOptions::MapEncoding::kRaw;
  // The ideal explorer maps with truth in SLAM's place; everything else is the same.
  std::optional<SlamNode> slam_node;
  std::optional<IdealMapperNode> ideal_node;
  if (method.ideal) {
    ideal_node.emplace(host.lcm(), slam_config.slam, slam_node_options);
  } else {
    slam_node.emplace(host.lcm(), slam_config.slam, slam_node_options);
  }
  FrontierNode frontier_node(host.lcm(), frontier_options);
  UtilityNode utility_node(host.lcm(), utility_options);
  NavNode nav_node(host.lcm(), nav_options);
  RunListener listener(host.lcm(), world.map.grid);

  // CPU per node (see NodeCpu): handlers charge their Subscriptions; the
  // runner times the simulator's ticks and its own evaluation.
  const double cpu_start_s = ThreadCpuSeconds();
  double sim_tick_cpu_s = 0.0;
  double evaluation_cpu_s = 0.0;
  auto node_cpu = [&] {
    NodeCpu cpu;
    cpu.sim_s = sim_tick_cpu_s + sim_node.subscriptions().total_cpu_s();
    cpu.slam_s = slam_node ? slam_node->subscriptions().total_cpu_s()
                           : ideal_node->subscriptions().total_cpu_s();
    cpu.frontier_s = frontier_node.subscriptions().total_cpu_s();
    cpu.utility_s = utility_node.subscriptions().total_cpu_s();
    cpu.nav_s = nav_node.subscriptions().total_cpu_s();
    cpu.evaluation_s = evaluation_cpu_s + listener.subscriptions().total_cpu_s();
    cpu.other_s = ThreadCpuSeconds() - cpu_start_s - cpu.total_s();
    return cpu;
  };

  ExploreResult result;
  const int64_t end_us = std::llround(options.duration_s * 1e6);
  const int64_t progress_us = std::llround(options.progress_period_s * 1e6);
  int64_t next_sample_us = 1'000'000;
  int64_t next_progress_us = progress_us;
  int64_t next_cost_us = kCostPeriodUs;
  result.cost.push_back({0.0, 0.0, node_cpu()});
  bool interrupted = false;
  const Clock::time_point wall_start = Clock::now();

  auto wall_seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - wall_start).count();
  };
  auto progress = [&] { return listener.Progress(simulator.utime() * 1e-6, wall_seconds()); };

  host.Run(
      [&] {
        if (simulator.utime() >= end_us) return false;
        const double tick_start_s = ThreadCpuSeconds();
        sim_node.Tick();
        sim_tick_cpu_s += ThreadCpuSeconds() - tick_start_s;
        return true;
      },
      [&] {
        const int64_t now_us = simulator.utime();
        if (now_us >= next_sample_us) {
          const double sample_start_s = ThreadCpuSeconds();
          result.coverage.push_back({now_us * 1e-6, listener.coverage()});
          result.uncertainty.push_back({now_us * 1e-6, listener.mean_edge_d_opt()});
          next_sample_us += 1'000'000;
          evaluation_cpu_s += ThreadCpuSeconds() - sample_start_s;
        }
        if (now_us >= next_cost_us) {
          result.cost.push_back({now_us * 1e-6, wall_seconds(), node_cpu()});
          next_cost_us += kCostPeriodUs;
        }
        if (on_progress && progress_us > 0 && now_us >= next_progress_us) {
          on_progress(progress());
          next_progress_us += progress_us;
        }
        if (stop && stop->load()) {
          interrupted = true;
          return false;
        }
        return !listener.done() && !listener.stopped();
      });
  const double wall_s = wall_seconds();
  const double sim_s = simulator.utime() * 1e-6;
  if (result.cost.empty() || result.cost.back().t_s < sim_s) {
    result.cost.push_back({sim_s, wall_s, node_cpu()});
  }

  // The final state straight from SLAM: newer than its last (rate-limited) SLAM_MAP.
  const double finish_start_s = ThreadCpuSeconds();
  result.map = slam_node ? slam_node->slam().RenderMap() : ideal_node->mapper().RenderMap();
  result.graph = slam_node ? slam_node->slam().graph() : ideal_node->mapper().graph();
  FinishResult(listener, world, options, method.name(), sim_s, wall_s, &result);
  evaluation_cpu_s += ThreadCpuSeconds() - finish_start_s;
  RunMetrics& m = result.metrics;
  m.node_cpu = node_cpu();
  m.sim_per_cpu = SimSecondsPerCpuSecond(result.cost, 0.0, sim_s);
  if (sim_s >= 2 * kRateWindowS) {  // two disjoint windows, to compare
    m.sim_per_cpu_first_300s = SimSecondsPerCpuSecond(result.cost, 0.0, kRateWindowS);
    m.sim_per_cpu_last_300s = SimSecondsPerCpuSecond(result.cost, sim_s - kRateWindowS, sim_s);
  }
  m.collisions = simulator.collisions();
  m.goals_reached = utility_node.goals_reached();
  m.goals_failed = utility_node.goals_failed();
  m.decisions = utility_node.decisions();
  m.done = listener.done();
  m.end_reason = m.done               ? "done"
                 : listener.stopped() ? "stopped"
                 : interrupted        ? "interrupted"
                                      : "duration";
  if (on_progress) on_progress(listener.FinalProgress(m, sim_s, wall_s));
  return result;
}

}  // namespace aslam
