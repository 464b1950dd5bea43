#include "eval/bench.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

namespace aslam {
namespace {

namespace fs = std::filesystem;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteFile(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

int CountLines(const std::string& text) {
  int n = 0;
  for (const char c : text) n += c == '\n';
  return n;
}

std::string TempDir(const std::string& name) {
  const std::string dir = testing::TempDir() + "/bench_test_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

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

TEST(MeanStdTest, SampleStandardDeviationOverFiniteValues) {
  const MeanStd m = ComputeMeanStd({2.0, 4.0, std::nan(""), 4.0, 4.0, 5.0, 5.0, 7.0, 9.0});
  EXPECT_EQ(m.n, 8);
  EXPECT_DOUBLE_EQ(m.mean, 5.0);
  EXPECT_DOUBLE_EQ(m.std, std::sqrt(32.0 / 7.0));
  EXPECT_EQ(ComputeMeanStd({3.0}).std, 0.0);
  EXPECT_EQ(ComputeMeanStd({}).n, 0);
}

TEST(ReadFinishedRunTest, InterruptedOrTornRunsAreNotFinished) {
  const std::string dir = TempDir("finished");
  BenchRun run{"w", "w", "fd", 1, dir + "/run"};
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json", "{\n  \"coverage\": 0.5,\n  \"end_reason\": \"interrupted\"\n}\n");
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json", "{\n  \"coverage\": 0.5,\n  \"end_reas");
  EXPECT_FALSE(ReadFinishedRun(run));
  WriteFile(run.dir + "/metrics.json",
            "{\n  \"coverage\": 0.5,\n  \"time_to_90_coverage_s\": null,\n  \"end_reason\": \"duration\"\n}\n");
  const auto record = ReadFinishedRun(run);
  ASSERT_TRUE(record);
  EXPECT_DOUBLE_EQ(record->Number("coverage"), 0.5);
  EXPECT_TRUE(std::isnan(record->Number("time_to_90_coverage_s")));
  EXPECT_TRUE(std::isnan(record->Number("no_such_key")));
}

// Hand-made runs: the tables' arithmetic and the curves' hold-last rule.
TEST(BenchReportTest, TablesAndCurvesFromKnownRuns) {
  const std::string dir = TempDir("tables");
  std::vector<RunRecord> records;
  const double coverages[] = {0.5, 0.7};
  const double reductions[] = {20.0, 30.0};
  for (int i = 0; i < 2; ++i) {
    RunRecord r;
    r.run = {"w", "w", "ours", i + 1, dir + "/ours_" + std::to_string(i)};
    r.fields = {{"coverage", std::to_string(coverages[i])},
                {"algebraic_connectivity", i == 0 ? "1.0" : "3.0"},
                {"d_opt_reduction_percent", std::to_string(reductions[i])},
                {"ssim", "null"}};
    records.push_back(r);
  }
  // Run 0 ends at 2 s (done): its last value holds for t = 3, 4.
  WriteFile(records[0].run.dir + "/coverage.csv", "t_s,coverage\n1.000,0.1\n2.000,0.5\n");
  WriteFile(records[0].run.dir + "/uncertainty.csv", "t_s,mean_edge_d_opt\n1.000,\n2.000,100\n");
  WriteFile(records[1].run.dir + "/coverage.csv", "t_s,coverage\n1.000,0.3\n2.000,0.4\n3.000,0.6\n4.000,0.7\n");
  WriteFile(records[1].run.dir + "/uncertainty.csv",
            "t_s,mean_edge_d_opt\n1.000,60\n2.000,80\n3.000,50\n4.000,40\n");

  const auto curves = ComputeCurves(records, 4.0);
  const std::vector<CurvePoint>& c = curves.at({"w", "ours"});
  ASSERT_EQ(c.size(), 4u);
  EXPECT_DOUBLE_EQ(c[0].coverage.mean, 0.2);
  EXPECT_DOUBLE_EQ(c[3].coverage.mean, 0.6);  // (0.5 held + 0.7) / 2
  EXPECT_EQ(c[0].d_opt.n, 1);                  // run 0 had no edge yet
  EXPECT_DOUBLE_EQ(c[0].d_opt.mean, 60.0);
  EXPECT_DOUBLE_EQ(c[1].d_opt.mean, 90.0);
  EXPECT_DOUBLE_EQ(c[3].d_opt.mean, 70.0);

  const std::string table1 = Table1Markdown(records, {"w"}, {"fd", "ours"});
  EXPECT_NE(table1.find("| w | fd | 0 |"), std::string::npos) << table1;
  EXPECT_NE(table1.find("| w | ours | 2 | 2.000 ± 1.414 |"), std::string::npos) << table1;
  EXPECT_NE(table1.find("0.600 ± 0.141"), std::string::npos) << table1;  // coverage
  // Mean curve 60, 90, 75, 70: max 90, min 60, diff 30, %R 33.3; per run 25 ± 7.1.
  const std::string table2 = Table2Markdown(records, curves, {"w"}, {"ours"});
  EXPECT_NE(table2.find("| w | ours | 2 | 90.0 & 60.0 | 30.0 | 33.3 | 25.0 ± 7.1 |"), std::string::npos) << table2;

  const std::string csv = RunsCsv(records);
  EXPECT_EQ(CountLines(csv), 3);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "world_label,run_dir,coverage,algebraic_connectivity,d_opt_reduction_percent,ssim");
}

// Coverage at a sixth, a third, two thirds and all of the duration, and the
// median time to 90 % with never-reached runs counted as the latest.
TEST(BenchReportTest, CoverageTableFromKnownRuns) {
  const std::string dir = TempDir("coverage");
  std::vector<RunRecord> records;
  // (method, seed, time to 90 % or null, coverage series for seconds 1..6)
  const struct {
    const char* method;
    const char* time_to_90;
    const char* coverage_csv;
  } runs[] = {
      {"ours", "3.0", "t_s,coverage\n1,0.2\n2,0.5\n3,0.9\n4,0.9\n5,0.95\n6,0.95\n"},
      {"ours", "null", "t_s,coverage\n1,0.0\n2,0.3\n3,0.5\n4,0.6\n5,0.7\n6,0.8\n"},
      {"ours", "5.0", "t_s,coverage\n1,0.1\n2,0.4\n3,0.6\n4,0.7\n5,0.9\n"},  // done at 5 s: holds 0.9
      {"fd", "4.0", "t_s,coverage\n1,0.5\n2,0.6\n3,0.7\n4,0.9\n5,0.9\n6,0.9\n"},
      {"fd", "null", "t_s,coverage\n1,0.5\n2,0.6\n3,0.7\n4,0.8\n5,0.8\n6,0.8\n"},
  };
  int seed = 0;
  for (const auto& spec : runs) {
    RunRecord r;
    r.run = {"w", "w", spec.method, ++seed, dir + "/run_" + std::to_string(seed)};
    r.fields = {{"time_to_90_coverage_s", spec.time_to_90}};
    WriteFile(r.run.dir + "/coverage.csv", spec.coverage_csv);
    WriteFile(r.run.dir + "/uncertainty.csv", "t_s,mean_edge_d_opt\n");
    records.push_back(r);
  }
  const std::string table = CoverageMarkdown(records, ComputeCurves(records, 6.0), {"w"}, {"fd", "ours"}, 6.0);
  EXPECT_NE(table.find("| coverage % at 1 s | coverage % at 2 s | coverage % at 4 s | coverage % at 6 s |"),
            std::string::npos)
      << table;
  // ours at 1, 2, 4, 6 s: means 10, 40, 73.3, 88.3 %; sorted times 3, 5, never: median 5 s.
  EXPECT_NE(table.find("| w | ours | 3 | 10.0 ± 10.0 | 40.0 ± 10.0 | 73.3 ± 15.3 | 88.3 ± 7.6 | 5 s (2/3 reached) |"),
            std::string::npos)
      << table;
  // fd: times 4 and never; the median lies past the end.
  EXPECT_NE(table.find("| w | fd | 2 | 50.0 ± 0.0 | 60.0 ± 0.0 | 85.0 ± 7.1 | 85.0 ± 7.1 | > 6 s (1/2 reached) |"),
            std::string::npos)
      << table;
}

// Reference p-values from scipy.stats.mannwhitneyu(method="asymptotic"), which
// uses the same normal approximation with tie and continuity corrections.
TEST(MannWhitneyTest, MatchesTheNormalApproximation) {
  EXPECT_NEAR(MannWhitneyP({1, 2, 3}, {4, 5, 6}), 0.08085559837005224, 1e-12);
  EXPECT_NEAR(MannWhitneyP({4, 5, 6}, {1, 2, 3}), 0.08085559837005224, 1e-12);  // two-sided
  EXPECT_NEAR(MannWhitneyP({1, 1, 2}, {2, 3, 3}), 0.11014892418594699, 1e-12);  // ties
  EXPECT_NEAR(MannWhitneyP({3, 5, INFINITY}, {4, INFINITY, INFINITY}), 0.6428348264908044, 1e-12);
  std::vector<double> low, high;
  for (int i = 1; i <= 15; ++i) {
    low.push_back(i);
    high.push_back(i + 15);
  }
  EXPECT_NEAR(MannWhitneyP(low, high), 3.3918213908250945e-06, 1e-15);
  EXPECT_DOUBLE_EQ(MannWhitneyP({1, 2, 3}, {1, 2, 3}), 1.0);
  EXPECT_DOUBLE_EQ(MannWhitneyP({2, 2}, {2, 2}), 1.0);
  EXPECT_NEAR(MannWhitneyP({1, NAN, 2, 3}, {4, 5, 6}), 0.08085559837005224, 1e-12);  // NaN dropped
  EXPECT_TRUE(std::isnan(MannWhitneyP({}, {1, 2})));
}

TEST(BenchReportTest, ComparisonAgainstTheReferenceMethod) {
  std::vector<RunRecord> records;
  const struct {
    const char* method;
    const char* coverage;
    const char* time_to_90;
  } runs[] = {{"ours", "0.9", "3"}, {"ours", "0.8", "5"}, {"ours", "1.0", "null"},
              {"fd", "0.5", "4"},   {"fd", "0.6", "null"}, {"fd", "0.7", "null"}};
  int seed = 0;
  for (const auto& spec : runs) {
    RunRecord r;
    r.run = {"w", "w", spec.method, ++seed, "unused"};
    r.fields = {{"coverage", spec.coverage}, {"time_to_90_coverage_s", spec.time_to_90}};
    records.push_back(r);
  }
  EXPECT_EQ(ReferenceMethod({"fd", "ours", "ags"}), "ours");
  EXPECT_EQ(ReferenceMethod({"fd", "ags"}), "ags");
  const std::string table = ComparisonMarkdown(records, {"w"}, {"fd", "ours"}, 6.0);
  EXPECT_NE(table.find("| world | metric | fd | ours | ours vs fd |"), std::string::npos) << table;
  // Means 0.6 and 0.9: +50 %, and the samples are fully separated (p of 3 vs 3).
  EXPECT_NE(table.find("| w | coverage | 0.600 | 0.900 | +50.0 % (p = 0.081) |"), std::string::npos)
      << table;
  // Medians: fd's lies past the end, so no relative difference; p ranks never-reached runs last.
  EXPECT_NE(table.find("| w | time to 90 % coverage (median) | > 6 s | 5 s | – (p = 0.64) |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("| w | A.C | – | – | – |"), std::string::npos) << table;  // no values at all
}

// The whole command on the test world: 2 seeds x 3 methods, every output,
// then a resumed bench that skips what is finished.
TEST(RunBenchTest, SmallMatrixWritesEveryOutputAndResumes) {
  BenchOptions options;
  options.worlds = {"test"};
  options.seeds = 2;
  options.duration_s = 40.0;
  options.jobs = 2;
  options.config_file = std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml";
  options.out_dir = TempDir("matrix");
  options.aslam_binary = ASLAM_BINARY;

  const BenchSummary first = RunBench(options, nullptr, {});
  EXPECT_EQ(first.total, 6);
  EXPECT_EQ(first.skipped, 0);
  EXPECT_EQ(first.finished, 6);
  EXPECT_TRUE(first.failed.empty());
  const std::vector<std::string> written = WriteBenchReports(options);
  for (const std::string name :
       {"runs.csv", "table1.md", "table2.md", "coverage.md", "comparison.md", "curves.csv", "fig3.png", "fig4.png",
        "fig5_test.png"}) {
    EXPECT_NE(std::find(written.begin(), written.end(), name), written.end()) << name;
    EXPECT_GT(fs::file_size(options.out_dir + "/" + name), 100u) << name;
  }
  EXPECT_EQ(CountLines(ReadFile(options.out_dir + "/runs.csv")), 7);
  // Fig. 5's truth image reads like the world's map.pgm (top row first): walls dark, free space white.
  const cv::Mat pgm = cv::imread(std::string(ASLAM_SOURCE_DIR) + "/worlds/test/map.pgm", cv::IMREAD_GRAYSCALE);
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
  for (const std::string method : {"fd", "ags", "ours"}) {
    EXPECT_NE(table1.find("| test | " + method + " | 2 |"), std::string::npos) << table1;
  }

  const BenchSummary again = RunBench(options, nullptr, {});
  EXPECT_EQ(again.skipped, 6);
  EXPECT_EQ(again.finished, 0);

  fs::remove(options.out_dir + "/runs/test/ags/seed_02/metrics.json");
  const BenchSummary resumed = RunBench(options, nullptr, {});
  EXPECT_EQ(resumed.skipped, 5);
  EXPECT_EQ(resumed.finished, 1);
  EXPECT_TRUE(fs::exists(options.out_dir + "/runs/test/ags/seed_02/metrics.json"));
}

}  // namespace
}  // namespace aslam
