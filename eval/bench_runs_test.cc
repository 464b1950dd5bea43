#include "eval/bench_runs.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

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
  const std::string dir = TempDir("finished");
  BenchRun run{"w", "w", "fd", 1, dir + "/run"};
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
}

}  // namespace
}  // namespace aslam
