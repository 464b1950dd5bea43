#include "eval/nav_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "common/text_format.h"
#include "common/world_file.h"
#include "eval/stats.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"

namespace aslam {
namespace {

// Runs one pair, printing the loop's state every `period_s` of simulated time.
void TraceGoalRun(const OccupancyGrid& map, const GoalPair& pair, const NavOptions& nav_options,
                  uint64_t sim_seed, double timeout_s, double period_s) {
  SimulatorOptions sim;
  sim.seed = sim_seed;
  NavClosedLoop loop(map, pair.start, nav_options, sim);
  loop.SendGoal(1, pair.goal);
  int64_t next_utime = 0;
  loop.RunUntil(
      [&] {
        if (loop.utime() < next_utime) return false;
        next_utime += static_cast<int64_t>(period_s * 1e6);
        const Pose2d& pose = loop.simulator().true_pose();
        const Twist2d& v = loop.simulator().true_velocity();
        const Navigator& nav = loop.nav().navigator();
        const NavStatus& s = nav.status();
        const DwaResult& dwa = nav.last_dwa();
        std::printf(
            "t %6.1f  pose (%6.2f, %6.2f, %5.2f)  v %5.2f w %5.2f  %-8s %-8s rem %6.2f  "
            "dwa %s cmd (%5.2f, %5.2f) %d/%d colliding  %s\n",
            loop.utime() * 1e-6, pose.x_m, pose.y_m, pose.yaw_rad, v.linear_mps, v.angular_radps,
            NavStateName(s.state), RecoveryPhaseName(s.recovery), s.distance_remaining_m,
            dwa.found ? "ok" : "--", dwa.command.linear_mps, dwa.command.angular_radps,
            dwa.trajectories_colliding, dwa.trajectories_evaluated, s.detail.c_str());
        return s.state != NavState::kActive;
      },
      timeout_s);
}

// The bench itself; throws on a failure.
int Run(const NavBenchOptions& options) {
  const NavOptions nav_options = LoadNavOptionsFromFile(options.config_path);
  const WorldInfo world = LoadWorld(options.world);
  const OccupancyGrid& map = world.map.grid;
  const std::vector<GoalPair> pairs = DrawGoalPairs(map, nav_options, options.runs, options.seed,
                                                    options.min_distance_m, options.clearance_m);
  if (options.trace_run >= 0) {
    if (options.trace_run >= static_cast<int>(pairs.size())) {
      throw std::runtime_error("--trace: no such run");
    }
    TraceGoalRun(map, pairs[options.trace_run], nav_options,
                 static_cast<uint64_t>(options.seed) + options.trace_run, options.timeout_s,
                 options.trace_period_s);
    return 0;
  }
  std::printf("aslam-nav-bench: %s, %d runs, seed %lld, timeout %.0f s\n", options.world.c_str(),
              options.runs, static_cast<long long>(options.seed), options.timeout_s);

  NavBenchTally tally;
  const auto wall_start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    SimulatorOptions sim;
    sim.seed = static_cast<uint64_t>(options.seed) + i;
    const GoalRunResult result =
        RunGoal(map, pairs[i].start, pairs[i].goal, nav_options, sim, options.timeout_s);
    tally.Add(pairs[i], result);
    if (options.verbose) {
      std::fputs(FormatGoalRun(i, pairs[i], result).c_str(), stdout);
      std::fflush(stdout);
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::fputs(FormatTally(tally).c_str(), stdout);
  std::printf("simulated %.0f s in %.1f s wall (%.0fx real time)\n", tally.simulated_s, wall_s,
              wall_s > 0 ? tally.simulated_s / wall_s : 0.0);
  return tally.all_reached_without_collision() ? 0 : 3;
}

}  // namespace

int RunNavBench(const NavBenchOptions& options) {
  try {
    return Run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-nav-bench: %s\n", e.what());
    return 1;
  }
}

std::vector<GoalPair> DrawGoalPairs(const OccupancyGrid& map, const NavOptions& nav_options,
                                    int count, uint64_t seed, double min_distance_m,
                                    double clearance_m) {
  const Costmap costmap(map, nav_options.costmap);
  const GlobalPlanner planner(nav_options.global_planner);
  std::vector<CellIndex> candidates;
  for (int row = 0; row < map.height_cells(); ++row) {
    for (int col = 0; col < map.width_cells(); ++col) {
      const CellIndex cell{col, row};
      if (map.at(cell) == OccupancyGrid::kFree && costmap.ObstacleDistanceM(cell) >= clearance_m) {
        candidates.push_back(cell);
      }
    }
  }
  if (candidates.empty()) throw std::runtime_error("no free cell with the requested clearance");
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
  std::vector<GoalPair> pairs;
  for (int attempts = 0; static_cast<int>(pairs.size()) < count; ++attempts) {
    if (attempts > 100 * count + 1000) {
      throw std::runtime_error("cannot draw enough reachable pairs");
    }
    const Point2d a = map.CellCenter(candidates[pick(rng)]);
    const Point2d b = map.CellCenter(candidates[pick(rng)]);
    const double heading = yaw(rng);
    if (std::hypot(a.x_m - b.x_m, a.y_m - b.y_m) < min_distance_m) continue;
    const auto path = planner.Plan(costmap, a, b);
    if (!path) continue;
    pairs.push_back({{a.x_m, a.y_m, heading}, b, path->length_m});
  }
  return pairs;
}

std::string FormatGoalRun(std::size_t index, const GoalPair& pair, const GoalRunResult& result) {
  return Format(
      "run %3zu  (%6.2f, %6.2f, %5.2f) -> (%6.2f, %6.2f)  plan %5.1f m  %-11s  "
      "%6.1f s  driven %5.1f m  %.2f m/s  gap %.2f m  collisions %lld  recoveries %d%s%s\n",
      index, pair.start.x_m, pair.start.y_m, pair.start.yaw_rad, pair.goal.x_m, pair.goal.y_m,
      pair.path_length_m, NavStateName(result.state), result.time_s, result.distance_traveled_m,
      result.time_s > 0 ? result.distance_traveled_m / result.time_s : 0.0, result.min_clearance_m,
      static_cast<long long>(result.collisions), result.recoveries_used,
      result.detail.empty() ? "" : "  ", result.detail.c_str());
}

void NavBenchTally::Add(const GoalPair& pair, const GoalRunResult& result) {
  ++runs;
  simulated_s += result.time_s;
  collisions += result.collisions;
  runs_with_collision += result.collisions > 0 ? 1 : 0;
  recoveries += result.recoveries_used;
  min_gap_m = std::min(min_gap_m, result.min_clearance_m);
  if (result.state != NavState::kReached) return;
  ++reached;
  reached_time_s += result.time_s;
  reached_distance_m += result.distance_traveled_m;
  reached_path_m += pair.path_length_m;
  reached_times_s.push_back(result.time_s);
  reached_speeds_mps.push_back(result.distance_traveled_m / result.time_s);
}

std::string FormatTally(const NavBenchTally& tally) {
  std::string text = Format(
      "\nsuccess %d/%d (%.0f %%)  runs with a collision %d  collisions %lld  recoveries %d  "
      "smallest robot-wall gap %.2f m\n",
      tally.reached, tally.runs, 100.0 * tally.reached / tally.runs, tally.runs_with_collision,
      static_cast<long long>(tally.collisions), tally.recoveries, tally.min_gap_m);
  // Means and medians of no run would be meaningless (stats' Median is NaN there).
  if (tally.reached > 0) {
    text += Format(
        "reached runs: mean speed %.3f m/s (driven / time), median %.3f m/s; "
        "time to goal mean %.1f s, median %.1f s; driven / planned length %.3f\n",
        tally.reached_distance_m / tally.reached_time_s, Median(tally.reached_speeds_mps),
        tally.reached_time_s / tally.reached, Median(tally.reached_times_s),
        tally.reached_distance_m / tally.reached_path_m);
  }
  return text;
}

}  // namespace aslam
