#include "eval/explore_runner.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "common/config.h"
#include "common/map_io.h"
#include "common/test_temp_dir.h"
#include "eval/explore_process.h"
#include "eval/run_outputs.h"
#include "slam/g2o_io.h"

namespace aslam {
namespace {

const std::string kRoot = ASLAM_SOURCE_DIR;

ExploreOptions TestWorld(const std::string& method) {
  ExploreOptions o;
  o.world = kRoot + "/worlds/test";
  o.method = method;
  o.duration_s = 600.0;  // the test world is done in about 240 s
  o.seed = 1;
  o.config_file = kRoot + "/config/aslam.yaml";
  o.progress_period_s = 0.0;
  return o;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every node is charged CPU, the parts add up, and the timeline is cumulative.
void ExpectCostAccounted(const ExploreResult& r) {
  const RunMetrics& m = r.metrics;
  ASSERT_TRUE(m.node_cpu.has_value());
  const NodeCpu& cpu = *m.node_cpu;
  for (const double node_s :
       {cpu.sim_s, cpu.slam_s, cpu.frontier_s, cpu.utility_s, cpu.nav_s, cpu.evaluation_s}) {
    EXPECT_GT(node_s, 0.0);
  }
  EXPECT_GE(cpu.other_s, 0.0);
  EXPECT_NEAR(cpu.total_s(),
              cpu.sim_s + cpu.slam_s + cpu.frontier_s + cpu.utility_s + cpu.nav_s +
                  cpu.evaluation_s + cpu.other_s,
              1e-12);
  ASSERT_GE(r.cost.size(), 2u);
  EXPECT_EQ(r.cost.front().t_s, 0.0);
  EXPECT_NEAR(r.cost.back().t_s, m.sim_seconds, 1e-9);
  for (std::size_t i = 1; i < r.cost.size(); ++i) {
    EXPECT_GT(r.cost[i].t_s, r.cost[i - 1].t_s);
    EXPECT_GE(r.cost[i].cpu.slam_s, r.cost[i - 1].cpu.slam_s);
    EXPECT_GE(r.cost[i].cpu.total_s(), r.cost[i - 1].cpu.total_s());
  }
  // The run's last cost sample precedes the final evaluation, which is charged too.
  EXPECT_GT(cpu.evaluation_s, r.cost.back().cpu.evaluation_s);
  ASSERT_TRUE(m.sim_per_cpu.has_value());
  const double run_cpu_s = r.cost.back().cpu.total_s() - r.cost.front().cpu.total_s();
  EXPECT_NEAR(*m.sim_per_cpu, m.sim_seconds / run_cpu_s, 1e-9 * *m.sim_per_cpu);
  EXPECT_EQ(m.sim_per_cpu_first_300s.has_value(), m.sim_seconds >= 600.0);
  EXPECT_EQ(m.sim_per_cpu_last_300s.has_value(), m.sim_seconds >= 600.0);
}

// goals.csv's ledger (from the bus) agrees with the utility's own counters, and every goal's
// times are in order.
void ExpectGoalsAccounted(const ExploreResult& r) {
  const RunMetrics& m = r.metrics;
  int total = 0, reached = 0, failed = 0;
  for (const auto& [outcome, count] : m.goal_outcomes) {
    total += count;
    if (outcome == "reached") reached = count;
    if (outcome == "failed" || outcome == "unreachable") failed += count;
  }
  EXPECT_EQ(total, static_cast<int>(r.goals.size()));
  EXPECT_EQ(reached, m.goals_reached);
  EXPECT_EQ(failed, m.goals_failed);
  EXPECT_LE(static_cast<int>(r.goals.size()), m.decisions);
  int by_reason = 0;
  for (const auto& [reason, count] : m.goal_failures_by_reason) by_reason += count;
  EXPECT_EQ(by_reason, failed);
  for (std::size_t i = 0; i < r.goals.size(); ++i) {
    const GoalRecord& g = r.goals[i];
    if (i > 0) {
      EXPECT_GT(g.goal_id, r.goals[i - 1].goal_id);
      EXPECT_GE(g.chosen_at_s, r.goals[i - 1].chosen_at_s);
    }
    if (g.ended_at_s) {
      EXPECT_GE(*g.ended_at_s, g.chosen_at_s) << "goal " << g.goal_id;
    }
    EXPECT_EQ(g.ended_at_s.has_value(), g.outcome != GoalOutcome::kOpen) << "goal " << g.goal_id;
    EXPECT_GE(g.driven_m, 0.0);
  }
  ASSERT_FALSE(r.goals.empty());
  EXPECT_TRUE(r.goals.front().path_length_at_choice_m.has_value());
}

class ExploreMethodTest : public ::testing::TestWithParam<std::string> {};

// Issue 6: each method explores the test world to `done`, >= 95 % covered, without touching a wall.
TEST_P(ExploreMethodTest, TestWorldExploredToDoneWithoutCollision) {
  const ExploreResult r = RunExploreInProcess(TestWorld(GetParam()));
  const RunMetrics& m = r.metrics;
  EXPECT_TRUE(m.done) << "ended by " << m.end_reason << " at " << m.sim_seconds << " s";
  EXPECT_EQ(m.end_reason, "done");
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_EQ(m.collisions, 0);
  EXPECT_EQ(m.method, GetParam());
  EXPECT_GT(m.keyframes, 50);
  EXPECT_EQ(m.ate_matched, m.keyframes);  // every keyframe has truth
  EXPECT_LT(m.ate_rmse_m, 0.2);
  ASSERT_TRUE(m.time_to_90_coverage_s.has_value());
  EXPECT_LT(*m.time_to_90_coverage_s, m.sim_seconds + 1e-9);
  EXPECT_FALSE(r.map.empty());
  EXPECT_EQ(static_cast<int>(r.graph.nodes.size()), m.keyframes);
  ExpectCostAccounted(r);
  ExpectGoalsAccounted(r);
  EXPECT_TRUE(m.stuck_episodes.empty());
  if (GetParam() == "ideal") {
    EXPECT_LT(m.ate_rmse_m, 1e-6);  // it maps with the true pose
  }
  std::printf(
      "[ measured ] %s: coverage %.4f, done at %.1f s, ATE RMSE %.3f m, %d keyframes, "
      "%d loop closures, goals %d reached %d failed\n",
      GetParam().c_str(), m.coverage, m.sim_seconds, m.ate_rmse_m, m.keyframes, m.loop_closures,
      m.goals_reached, m.goals_failed);
}

INSTANTIATE_TEST_SUITE_P(Methods, ExploreMethodTest,
                         ::testing::Values("fd", "ags", "ours", "ideal"),
                         [](const auto& info) { return info.param; });

// docs/architecture.md §4: in-process runs are deterministic for a seed; only the wall time
// differs.
TEST(ExploreRunnerTest, SameSeedGivesIdenticalMetricsAndTimeline) {
  ExploreResult a = RunExploreInProcess(TestWorld("ours"));
  ExploreResult b = RunExploreInProcess(TestWorld("ours"));
  for (RunMetrics* m : {&a.metrics, &b.metrics}) {  // the clock's figures
    m->wall_seconds = 0.0;
    m->node_cpu.reset();
    m->sim_per_cpu.reset();
  }
  EXPECT_EQ(MetricsToJson(a.metrics), MetricsToJson(b.metrics));
  EXPECT_EQ(CoverageToCsv(a.coverage), CoverageToCsv(b.coverage));
  ASSERT_EQ(a.graph.nodes.size(), b.graph.nodes.size());
  for (std::size_t i = 0; i < a.graph.nodes.size(); ++i) {
    EXPECT_EQ(a.graph.nodes[i].pose.x_m, b.graph.nodes[i].pose.x_m) << i;
    EXPECT_EQ(a.graph.nodes[i].pose.y_m, b.graph.nodes[i].pose.y_m) << i;
  }
  EXPECT_EQ(a.map.cells(), b.map.cells());
}

TEST(ExploreRunnerTest, RunFolderHoldsEveryFileConsistentWithTheMetrics) {
  const ExploreResult r = RunExploreInProcess(TestWorld("ours"));
  const std::string dir = TestTempPath("run");
  std::filesystem::remove_all(dir);
  WriteRunFolder(r, dir);
  for (const char* f : {"map.yaml", "map.pgm", "map.png", "graph.g2o", "coverage.csv", "goals.csv",
                        "metrics.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
  // goals.csv: a header and a row per goal.
  std::istringstream goals_csv(ReadFile(dir + "/goals.csv"));
  std::string goals_line;
  std::getline(goals_csv, goals_line);
  EXPECT_EQ(goals_line.rfind("goal_id,frontier_id,", 0), 0u) << goals_line;
  std::size_t goal_rows = 0;
  while (std::getline(goals_csv, goals_line)) ++goal_rows;
  EXPECT_EQ(goal_rows, r.goals.size());
  const YAML::Node metrics = YAML::LoadFile(dir + "/metrics.json");
  const int keyframes = metrics["keyframes"].as<int>();
  const double coverage = metrics["coverage"].as<double>();
  EXPECT_EQ(keyframes, r.metrics.keyframes);

  const LoadedMap map = LoadMap(dir + "/map.yaml");
  EXPECT_EQ(map.grid.width_cells(), r.map.width_cells());
  EXPECT_EQ(map.grid.height_cells(), r.map.height_cells());

  const PoseGraph graph = ReadG2o(dir + "/graph.g2o");
  EXPECT_EQ(static_cast<int>(graph.nodes.size()), keyframes);
  int closures = 0;
  for (const PoseGraphEdge& e : graph.edges) closures += e.kind == EdgeKind::kLoopClosure;
  EXPECT_EQ(closures, metrics["loop_closures"].as<int>());

  // coverage.csv: header, rows in time order, never dropping much (a loop
  // closure can re-render a little less), ending at the metrics' coverage.
  std::istringstream csv(ReadFile(dir + "/coverage.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "t_s,coverage");
  std::vector<CoverageSample> rows;
  while (std::getline(csv, line)) {
    CoverageSample s;
    char comma = 0;
    std::istringstream in(line);
    ASSERT_TRUE(in >> s.t_s >> comma >> s.coverage) << line;
    rows.push_back(s);
  }
  ASSERT_GT(rows.size(), 100u);
  double best = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(rows[i].t_s, rows[i - 1].t_s) << i;
    }
    EXPECT_GE(rows[i].coverage, best - 0.05) << "t=" << rows[i].t_s;
    best = std::max(best, rows[i].coverage);
  }
  EXPECT_NEAR(rows.back().t_s, metrics["sim_seconds"].as<double>(), 1e-3);
  EXPECT_NEAR(rows.back().coverage, coverage, 1e-6);
  std::filesystem::remove_all(dir);
}

// Ctrl-C: the run stops where it is and still returns everything to write.
TEST(ExploreRunnerTest, StopFlagEndsTheRunEarlyWithResults) {
  std::atomic<bool> stop{false};
  ExploreOptions o = TestWorld("fd");
  o.progress_period_s = 20.0;
  int reports = 0;
  const ExploreResult r = RunExploreInProcess(o, &stop, [&](const ExploreProgress& p) {
    ++reports;
    if (p.sim_s >= 20.0) stop = true;
  });
  EXPECT_EQ(r.metrics.end_reason, "interrupted");
  EXPECT_FALSE(r.metrics.done);
  EXPECT_NEAR(r.metrics.sim_seconds, 20.0, 0.05);
  EXPECT_EQ(reports, 2);  // at 20 s and the final one
  EXPECT_GT(r.metrics.keyframes, 0);
  EXPECT_GT(r.metrics.coverage, 0.1);
  ASSERT_FALSE(r.coverage.empty());
  EXPECT_NEAR(r.coverage.back().coverage, r.metrics.coverage, 1e-12);
}

// utility.return_home (aslam explore --return-home): done only once the robot is back at the
// start; the same run without it ends where the last frontier was.
TEST(ExploreRunnerTest, ReturnHomeEndsDoneAtTheStart) {
  const ExploreResult away = RunExploreInProcess(TestWorld("fd"));
  ASSERT_TRUE(away.metrics.done);
  ASSERT_GE(away.slam_path.size(), 2u);
  const auto distance_from_start = [](const ExploreResult& r) {
    return std::hypot(r.slam_path.back().x_m - r.slam_path.front().x_m,
                      r.slam_path.back().y_m - r.slam_path.front().y_m);
  };
  ASSERT_GT(distance_from_start(away), 1.0) << "the test world's last frontier is at the start";

  ExploreOptions o = TestWorld("fd");
  const std::string config = TestTempPath("return_home.yaml");
  std::ofstream(config) << ApplyConfigOverrides(o.config_file,
                                                {ParseConfigOverride("utility.return_home=true")});
  o.config_file = config;
  const ExploreResult home = RunExploreInProcess(o);
  EXPECT_TRUE(home.metrics.done);
  EXPECT_EQ(home.metrics.end_reason, "done");
  EXPECT_EQ(home.metrics.collisions, 0);
  EXPECT_GT(home.metrics.sim_seconds, away.metrics.sim_seconds);  // the way back took time
  EXPECT_LT(distance_from_start(home), 0.5);  // within the navigator's goal tolerance
  EXPECT_GE(home.metrics.coverage, 0.95);
  std::printf("[ measured ] return home: done at %.1f s (%.1f s without), %.2f m from the start\n",
              home.metrics.sim_seconds, away.metrics.sim_seconds, distance_from_start(home));
}

TEST(ExploreRunnerTest, DurationEndsTheRun) {
  ExploreOptions o = TestWorld("fd");
  o.duration_s = 5.0;
  const ExploreResult r = RunExploreInProcess(o);
  EXPECT_EQ(r.metrics.end_reason, "duration");
  EXPECT_NEAR(r.metrics.sim_seconds, 5.0, 1e-6);
  EXPECT_EQ(r.coverage.size(), 5u);  // one per simulated second, the last the final map's
}

TEST(ExploreRunnerTest, RateIsSimulatedOverCpuSecondsBetweenTheWindowsSamples) {
  auto sample = [](double t_s, double slam_s, double nav_s) {
    CostSample s;
    s.t_s = t_s;
    s.cpu.slam_s = slam_s;
    s.cpu.nav_s = nav_s;
    return s;
  };
  const std::vector<CostSample> cost = {sample(0, 0.5, 0), sample(10, 1.0, 0.5),
                                        sample(20, 2.0, 1.0), sample(30, 4.0, 2.0)};
  EXPECT_DOUBLE_EQ(*SimSecondsPerCpuSecond(cost, 0, 30), 30.0 / 5.5);
  EXPECT_DOUBLE_EQ(*SimSecondsPerCpuSecond(cost, 5, 25), 10.0 / 1.5);  // samples at 10 and 20
  EXPECT_DOUBLE_EQ(*SimSecondsPerCpuSecond(cost, 20, 30), 10.0 / 3.0);
  EXPECT_FALSE(SimSecondsPerCpuSecond(cost, 25, 29).has_value());  // no sample inside
  EXPECT_FALSE(SimSecondsPerCpuSecond(cost, 30, 30).has_value());  // no time spanned
  EXPECT_FALSE(SimSecondsPerCpuSecond({}, 0, 30).has_value());
}

TEST(ExploreRunnerTest, BadInputsThrowBeforeRunning) {
  ExploreOptions o = TestWorld("nearest");
  EXPECT_THROW(RunExploreInProcess(o), std::invalid_argument);
  o = TestWorld("fd");
  o.start = Pose2d{-100.0, -100.0, 0.0};  // off the map
  EXPECT_THROW(RunExploreInProcess(o), std::invalid_argument);
  o = TestWorld("ideal ");
  EXPECT_THROW(RunExploreInProcess(o), std::invalid_argument);
  // The ideal reads SIM_TRUTH in SLAM's place: process mode refuses it before starting anything.
  ExploreProcessOptions process;
  process.explore = TestWorld("ideal");
  process.out_dir = TestTempPath("ideal_process");
  try {
    RunExploreProcess(process);
    ADD_FAILURE() << "process mode ran the ideal explorer";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--inproc"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(process.out_dir));
  o = TestWorld("fd");
  o.world = kRoot + "/worlds/no_such_world";
  EXPECT_THROW(RunExploreInProcess(o), std::exception);
}

}  // namespace
}  // namespace aslam
