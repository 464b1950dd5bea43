// aslam-nav-bench: goal-reaching runs of the navigator in closed loop with
// the simulator, in-process on memq:// (true pose and true map stand in for
// SLAM). N seeded random start/goal pairs in a world; prints each run and the
// success rate, collisions, mean speed and time to goal.

#include <gflags/gflags.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/flags.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"
#include "eval/nav_closed_loop.h"
#include "navigation/nav_config.h"
#include "common/world_file.h"

DEFINE_string(world, "worlds/test", "world folder or map_server MAP.yaml");
DEFINE_string(config, "", "config file with a `nav:` section (default: built-in defaults)");
DEFINE_int32(runs, 20, "number of random start/goal pairs");
DEFINE_int64(seed, 1, "seed of the pairs (and, plus the run index, of the simulator)");
DEFINE_double(timeout, 240.0, "simulated seconds before a run counts as failed");
DEFINE_double(min_distance, 3.0, "minimum straight-line start-goal distance, m");
DEFINE_double(clearance, 0.4, "minimum obstacle distance of starts and goals, m");
DEFINE_bool(verbose, true, "print every run");
DEFINE_int32(trace, -1, "run only this pair, printing the loop every --trace_period seconds");
DEFINE_double(trace_period, 0.5, "simulated seconds between trace lines");

namespace aslam {
namespace {

struct Pair {
  Pose2d start;
  Point2d goal;
  double path_length_m = 0.0;
};

std::vector<Pair> DrawPairs(const OccupancyGrid& map, const NavOptions& options, int count,
                            uint64_t seed) {
  const Costmap costmap(map, options.costmap);
  const GlobalPlanner planner(options.global_planner);
  std::vector<CellIndex> candidates;
  for (int row = 0; row < map.height_cells(); ++row) {
    for (int col = 0; col < map.width_cells(); ++col) {
      const CellIndex cell{col, row};
      if (map.at(cell) == OccupancyGrid::kFree &&
          costmap.ObstacleDistanceM(cell) >= FLAGS_clearance) {
        candidates.push_back(cell);
      }
    }
  }
  if (candidates.empty()) throw std::runtime_error("no free cell with the requested clearance");
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  std::uniform_real_distribution<double> yaw(-M_PI, M_PI);
  std::vector<Pair> pairs;
  for (int attempts = 0; static_cast<int>(pairs.size()) < count; ++attempts) {
    if (attempts > 100 * count + 1000)
      throw std::runtime_error("cannot draw enough reachable pairs");
    const Point2d a = map.CellCenter(candidates[pick(rng)]);
    const Point2d b = map.CellCenter(candidates[pick(rng)]);
    const double heading = yaw(rng);
    if (std::hypot(a.x_m - b.x_m, a.y_m - b.y_m) < FLAGS_min_distance) continue;
    const auto path = planner.Plan(costmap, a, b);
    if (!path) continue;
    pairs.push_back({{a.x_m, a.y_m, heading}, b, path->length_m});
  }
  return pairs;
}

void Trace(const OccupancyGrid& map, const Pair& p, const NavOptions& options, uint64_t seed) {
  SimulatorOptions sim;
  sim.seed = seed;
  NavClosedLoop loop(map, p.start, options, sim);
  loop.SendGoal(1, p.goal);
  int64_t next_utime = 0;
  loop.RunUntil(
      [&] {
        if (loop.utime() < next_utime) return false;
        next_utime += static_cast<int64_t>(FLAGS_trace_period * 1e6);
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
      FLAGS_timeout);
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int Run() {
  try {
    const NavOptions options = LoadNavOptionsFromFile(FLAGS_config);
    const WorldInfo world = LoadWorld(FLAGS_world);
    const OccupancyGrid& map = world.map.grid;
    const std::vector<Pair> pairs = DrawPairs(map, options, FLAGS_runs, FLAGS_seed);
    if (FLAGS_trace >= 0) {
      if (FLAGS_trace >= static_cast<int>(pairs.size()))
        throw std::runtime_error("--trace: no such run");
      Trace(map, pairs[FLAGS_trace], options, static_cast<uint64_t>(FLAGS_seed) + FLAGS_trace);
      return 0;
    }
    std::printf("aslam-nav-bench: %s, %d runs, seed %lld, timeout %.0f s\n", FLAGS_world.c_str(),
                FLAGS_runs, static_cast<long long>(FLAGS_seed), FLAGS_timeout);

    int reached = 0, collided_runs = 0;
    int64_t collisions = 0;
    int recoveries = 0;
    double min_gap_m = std::numeric_limits<double>::infinity();
    double sum_time_s = 0.0, sum_distance_m = 0.0, sum_path_m = 0.0, sim_s = 0.0;
    std::vector<double> times_s, speeds;
    const auto wall_start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const Pair& p = pairs[i];
      SimulatorOptions sim;
      sim.seed = static_cast<uint64_t>(FLAGS_seed) + i;
      const GoalRunResult r = RunGoal(map, p.start, p.goal, options, sim, FLAGS_timeout);
      sim_s += r.time_s;
      const bool ok = r.state == NavState::kReached;
      collisions += r.collisions;
      collided_runs += r.collisions > 0 ? 1 : 0;
      recoveries += r.recoveries_used;
      min_gap_m = std::min(min_gap_m, r.min_clearance_m);
      if (ok) {
        ++reached;
        sum_time_s += r.time_s;
        sum_distance_m += r.distance_traveled_m;
        sum_path_m += p.path_length_m;
        times_s.push_back(r.time_s);
        speeds.push_back(r.distance_traveled_m / r.time_s);
      }
      if (FLAGS_verbose) {
        std::printf(
            "run %3zu  (%6.2f, %6.2f, %5.2f) -> (%6.2f, %6.2f)  plan %5.1f m  %-11s  "
            "%6.1f s  driven %5.1f m  %.2f m/s  gap %.2f m  collisions %lld  recoveries %d%s%s\n",
            i, p.start.x_m, p.start.y_m, p.start.yaw_rad, p.goal.x_m, p.goal.y_m, p.path_length_m,
            NavStateName(r.state), r.time_s, r.distance_traveled_m,
            r.time_s > 0 ? r.distance_traveled_m / r.time_s : 0.0, r.min_clearance_m,
            static_cast<long long>(r.collisions), r.recoveries_used, r.detail.empty() ? "" : "  ",
            r.detail.c_str());
        std::fflush(stdout);
      }
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const int n = static_cast<int>(pairs.size());
    std::printf(
        "\nsuccess %d/%d (%.0f %%)  runs with a collision %d  collisions %lld  recoveries %d  "
        "smallest robot-wall gap %.2f m\n",
        reached, n, 100.0 * reached / n, collided_runs, static_cast<long long>(collisions),
        recoveries, min_gap_m);
    if (reached > 0) {
      std::printf(
          "reached runs: mean speed %.3f m/s (driven / time), median %.3f m/s; "
          "time to goal mean %.1f s, median %.1f s; driven / planned length %.3f\n",
          sum_distance_m / sum_time_s, Median(speeds), sum_time_s / reached, Median(times_s),
          sum_distance_m / sum_path_m);
    }
    std::printf("simulated %.0f s in %.1f s wall (%.0fx real time)\n", sim_s, wall_s,
                wall_s > 0 ? sim_s / wall_s : 0.0);
    return reached == n && collisions == 0 ? 0 : 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-nav-bench: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace aslam

int main(int argc, char** argv) {
  aslam::ParseFlags(
      &argc, &argv,
      "aslam-nav-bench [--world DIR] [--runs N] [--seed S] [--timeout S] [--config FILE]");
  return aslam::Run();
}
