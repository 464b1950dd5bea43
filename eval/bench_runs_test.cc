#include "eval/bench_runs.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/test_temp_dir.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

TEST(PlanBenchTest, SeedMajorOrderAndFolders) {
  BenchOptions options;
  options.worlds = {"test", std::string(ASLAM_SOURCE_DIR) + "/worlds/office/"};
  options.methods = {"fd", "ours"};
  options.seeds = 2;
  options.out_dir = "OUT";
  const std::vector<BenchRun> runs = PlanBench(options);
  ASSERT_EQ(runs.size(), 8u);
  EXPECT_EQ(runs[0].world_label, "test");
  EXPECT_EQ(runs[0].method, "fd");
  EXPECT_EQ(runs[0].seed, 1);
  EXPECT_EQ(runs[0].dir, "OUT/runs/test/fd/seed_01");
  EXPECT_EQ(runs[1].method, "ours");
  EXPECT_EQ(runs[2].world_label, "office");  // seed 1 on every world before seed 2
  EXPECT_EQ(runs[2].seed, 1);
  EXPECT_EQ(runs[4].seed, 2);
  EXPECT_EQ(runs[7].dir, "OUT/runs/office/ours/seed_02");
  EXPECT_EQ(runs[0].world, std::string(ASLAM_SOURCE_DIR) + "/worlds/test");
}

TEST(PlanBenchTest, BadOptionsNameTheProblem) {
  BenchOptions options;
  options.worlds = {"test"};
  options.out_dir = "OUT";
  auto error = [&](const BenchOptions& o) {
    try {
      PlanBench(o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BenchOptions bad = options;
  bad.methods = {"fd", "greedy"};
  EXPECT_NE(error(bad).find("'greedy'"), std::string::npos);
  bad = options;
  bad.worlds = {"no_such_world"};
  EXPECT_NE(error(bad).find("'no_such_world'"), std::string::npos);
  bad = options;
  bad.worlds = {"test", std::string(ASLAM_SOURCE_DIR) + "/worlds/test/map.yaml"};
  EXPECT_NE(error(bad).find("two worlds are named 'test'"), std::string::npos);
  bad = options;
  bad.seeds = 0;
  EXPECT_NE(error(bad).find("--seeds"), std::string::npos);
  EXPECT_EQ(error(options), "no error");
}

TEST(WorldLabelTest, FolderOrMapStem) {
  EXPECT_EQ(WorldLabel(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus"), "campus");
  EXPECT_EQ(WorldLabel(std::string(ASLAM_SOURCE_DIR) + "/worlds/campus/"), "campus");
  EXPECT_EQ(WorldLabel("/maps/lab_floor2.yaml"), "lab_floor2");
  EXPECT_EQ(WorldLabel("/maps/lab/map.yaml"), "lab");
}

TEST(ReadFinishedRunTest, InterruptedOrTornRunsAreNotFinished) {
  const std::string dir = FreshTestTempDir("finished");
  BenchRun run{"w", "w", "fd", 1, dir + "/run", "", ""};
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json",
            "{\n  \"coverage\": 0.5,\n  \"end_reason\": \"interrupted\"\n}\n");
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json", "{\n  \"coverage\": 0.5,\n  \"end_reas");
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json",
            "{\n  \"coverage\": 0.5,\n  \"time_to_90_coverage_s\": null,\n  \"end_reason\": "
            "\"duration\"\n}\n");
  const auto record = ReadFinishedRun(run);
  ASSERT_TRUE(record);
  EXPECT_DOUBLE_EQ(record->Number("coverage"), 0.5);
  EXPECT_TRUE(std::isnan(record->Number("time_to_90_coverage_s")));
  EXPECT_TRUE(std::isnan(record->Number("no_such_key")));
  // Nested objects (node_cpu_s) flatten to outer.inner.
  WriteFile(run.dir + "/metrics.json",
            "{\n  \"coverage\": 0.5,\n  \"node_cpu_s\": {\"slam\": 1.5, \"nav\": 2},\n  "
            "\"end_reason\": \"done\"\n}\n");
  const auto nested = ReadFinishedRun(run);
  ASSERT_TRUE(nested);
  EXPECT_DOUBLE_EQ(nested->Number("node_cpu_s.slam"), 1.5);
  EXPECT_DOUBLE_EQ(nested->Number("node_cpu_s.nav"), 2.0);
  EXPECT_EQ(nested->fields.back().first, "end_reason");
}

// With --set: seed by seed, then setting x world x method; folders and configs per setting.
TEST(PlanBenchTest, SweepOrderFoldersAndConfigs) {
  BenchOptions options;
  options.worlds = {"test", "office"};
  options.methods = {"fd", "ours"};
  options.seeds = 2;
  options.config_file = "base.yaml";
  options.out_dir = "OUT";
  options.sweep = {"utility.lambda=0.3,1.2"};
  const std::vector<BenchRun> runs = PlanBench(options);
  ASSERT_EQ(runs.size(), 16u);
  EXPECT_EQ(runs[0].dir, "OUT/runs/utility.lambda=0.3/test/fd/seed_01");
  EXPECT_EQ(runs[0].setting, "utility.lambda=0.3");
  EXPECT_EQ(runs[0].config_file, "OUT/settings/utility.lambda=0.3/config.yaml");
  EXPECT_EQ(runs[1].dir, "OUT/runs/utility.lambda=0.3/test/ours/seed_01");
  EXPECT_EQ(runs[2].dir, "OUT/runs/utility.lambda=0.3/office/fd/seed_01");
  EXPECT_EQ(runs[4].dir, "OUT/runs/utility.lambda=1.2/test/fd/seed_01");  // then the next setting
  EXPECT_EQ(runs[4].config_file, "OUT/settings/utility.lambda=1.2/config.yaml");
  EXPECT_EQ(runs[8].dir, "OUT/runs/utility.lambda=0.3/test/fd/seed_02");  // then the next seed
  EXPECT_EQ(runs[15].dir, "OUT/runs/utility.lambda=1.2/office/ours/seed_02");
  // Without --set the layout and config are the plain bench's.
  options.sweep.clear();
  const std::vector<BenchRun> plain = PlanBench(options);
  ASSERT_EQ(plain.size(), 8u);
  EXPECT_EQ(plain[0].dir, "OUT/runs/test/fd/seed_01");
  EXPECT_EQ(plain[0].setting, "");
  EXPECT_EQ(plain[0].config_file, "base.yaml");
  options.sweep = {"utility.lamda"};
  EXPECT_THROW(PlanBench(options), std::invalid_argument);
}

// Resuming skips the runs with a finished metrics.json, per setting: a sweep with other values
// finds none of them. /bin/true stands in for `aslam`: it writes nothing, so what it "runs" fails.
TEST(RunBenchTest, SweepResumesPerSetting) {
  BenchOptions options;
  options.worlds = {"test"};
  options.methods = {"fd"};
  options.seeds = 2;
  options.jobs = 1;
  options.out_dir = FreshTestTempDir("sweep_resume");
  options.aslam_binary = "/bin/true";
  options.sweep = {"utility.lambda=0.3,0.6"};
  const std::vector<BenchRun> runs = PlanBench(options);
  ASSERT_EQ(runs.size(), 4u);
  FakeFinishedRun(runs[0], {{"coverage", "0.5"}});  // lambda 0.3, seed 1
  FakeFinishedRun(runs[3], {{"coverage", "0.5"}});  // lambda 0.6, seed 2
  const BenchSummary summary = RunBench(options, nullptr, {});
  EXPECT_EQ(summary.total, 4);
  EXPECT_EQ(summary.skipped, 2);
  ASSERT_EQ(summary.failed.size(), 2u);
  EXPECT_EQ(summary.failed[0].run.dir, runs[1].dir);
  EXPECT_EQ(summary.failed[1].run.dir, runs[2].dir);
  EXPECT_EQ(summary.failed[0].why, "ended without a finished metrics.json");
  EXPECT_EQ(summary.failed[0].logs, (std::vector<std::string>{runs[1].dir + "/explore.log"}));
  EXPECT_TRUE(fs::exists(options.out_dir + "/settings/utility.lambda=0.6/config.yaml"));

  options.sweep = {"utility.lambda=0.6,1.2"};  // other values: only lambda 0.6's run counts
  const BenchSummary other = RunBench(options, nullptr, {});
  EXPECT_EQ(other.skipped, 1);
  EXPECT_EQ(other.failed.size(), 3u);
}

}  // namespace
}  // namespace aslam
