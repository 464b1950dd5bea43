#include "eval/bench.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_temp_dir.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

// The whole command on the test world: 2 seeds x 4 methods (the ideal's too), every output,
// then a resumed bench that skips what is finished.
TEST(RunBenchTest, SmallMatrixWritesEveryOutputAndResumes) {
  BenchOptions options;
  options.worlds = {"test"};
  options.seeds = 2;
  options.duration_s = 40.0;
  options.jobs = 2;
  options.config_file = std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml";
  options.out_dir = FreshTestTempDir("matrix");
  options.aslam_binary = ASLAM_BINARY;

  const BenchSummary first = RunBench(options, nullptr, {});
  EXPECT_EQ(first.total, 8);
  EXPECT_EQ(first.skipped, 0);
  EXPECT_EQ(first.finished, 8);
  EXPECT_TRUE(first.failed.empty());
  const std::vector<std::string> written = WriteBenchReports(options);
  for (const std::string name :
       {"runs.csv", "table1.md", "table2.md", "coverage.md", "comparison.md", "ideal.md",
        "goals.md", "curves.csv", "fig3.png", "fig4.png", "fig5_test.png"}) {
    EXPECT_NE(std::find(written.begin(), written.end(), name), written.end()) << name;
    EXPECT_GT(fs::file_size(options.out_dir + "/" + name), 100u) << name;
  }
  EXPECT_EQ(CountLines(ReadFile(options.out_dir + "/runs.csv")), 9);
  // Fig. 5's truth image reads like the world's map.pgm (top row first): walls dark, free space
  // white.
  const cv::Mat pgm =
      cv::imread(std::string(ASLAM_SOURCE_DIR) + "/worlds/test/map.pgm", cv::IMREAD_GRAYSCALE);
  const cv::Mat truth = cv::imread(options.out_dir + "/fig5_test_truth.png", cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(pgm.size(), truth.size());
  int disagreements = 0;
  for (int row = 0; row < pgm.rows; ++row) {
    for (int col = 0; col < pgm.cols; ++col) {
      const uint8_t p = pgm.at<uint8_t>(row, col);
      const uint8_t t = truth.at<uint8_t>(row, col);
      disagreements += (p < 50 && t != 0) || (p > 250 && t != 255);
    }
  }
  EXPECT_EQ(disagreements, 0);
  const std::string table1 = ReadFile(options.out_dir + "/table1.md");
  const std::string ideal = ReadFile(options.out_dir + "/ideal.md");
  const std::string goals = ReadFile(options.out_dir + "/goals.md");
  for (const std::string method : {"fd", "ags", "ours", "ideal"}) {
    EXPECT_NE(table1.find("| test | " + method + " | 2 |"), std::string::npos) << table1;
    EXPECT_NE(goals.find("| test | " + method + " | 2 |"), std::string::npos) << goals;
    // The ideal is the reference of the others, paired by seed.
    EXPECT_EQ(ideal.find("| test | " + method + " | 2 |") != std::string::npos, method != "ideal")
        << ideal;
  }

  const BenchSummary again = RunBench(options, nullptr, {});
  EXPECT_EQ(again.skipped, 8);
  EXPECT_EQ(again.finished, 0);

  fs::remove(options.out_dir + "/runs/test/ags/seed_02/metrics.json");
  const BenchSummary resumed = RunBench(options, nullptr, {});
  EXPECT_EQ(resumed.skipped, 7);
  EXPECT_EQ(resumed.finished, 1);
  EXPECT_TRUE(fs::exists(options.out_dir + "/runs/test/ags/seed_02/metrics.json"));
}

}  // namespace
}  // namespace aslam
