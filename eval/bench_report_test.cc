#include "eval/bench_report.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/test_temp_dir.h"
#include "eval/bench.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

// Hand-made runs: the tables' arithmetic and the curves' hold-last rule.
TEST(BenchReportTest, TablesAndCurvesFromKnownRuns) {
  const std::string dir = FreshTestTempDir("tables");
  std::vector<RunRecord> records;
  const double coverages[] = {0.5, 0.7};
  const double reductions[] = {20.0, 30.0};
  for (int i = 0; i < 2; ++i) {
    RunRecord r;
    r.run = {"w", "w", "ours", i + 1, dir + "/ours_" + std::to_string(i), "", ""};
    r.fields = {{"coverage", std::to_string(coverages[i])},
                {"algebraic_connectivity", i == 0 ? "1.0" : "3.0"},
                {"d_opt_reduction_percent", std::to_string(reductions[i])},
                {"ssim", "null"}};
    records.push_back(r);
  }
  // Run 0 ends at 2 s (done): its last value holds for t = 3, 4.
  WriteFile(records[0].run.dir + "/coverage.csv", "t_s,coverage\n1.000,0.1\n2.000,0.5\n");
  WriteFile(records[0].run.dir + "/uncertainty.csv", "t_s,mean_edge_d_opt\n1.000,\n2.000,100\n");
  WriteFile(records[1].run.dir + "/coverage.csv",
            "t_s,coverage\n1.000,0.3\n2.000,0.4\n3.000,0.6\n4.000,0.7\n");
  WriteFile(records[1].run.dir + "/uncertainty.csv",
            "t_s,mean_edge_d_opt\n1.000,60\n2.000,80\n3.000,50\n4.000,40\n");

  const auto curves = ComputeCurves(records, 4.0);
  const std::vector<CurvePoint>& c = curves.at({"w", "ours"});
  ASSERT_EQ(c.size(), 4u);
  EXPECT_DOUBLE_EQ(c[0].coverage.mean, 0.2);
  EXPECT_DOUBLE_EQ(c[3].coverage.mean, 0.6);  // (0.5 held + 0.7) / 2
  EXPECT_EQ(c[0].d_opt.n, 1);                 // run 0 had no edge yet
  EXPECT_DOUBLE_EQ(c[0].d_opt.mean, 60.0);
  EXPECT_DOUBLE_EQ(c[1].d_opt.mean, 90.0);
  EXPECT_DOUBLE_EQ(c[3].d_opt.mean, 70.0);

  const std::string table1 = Table1Markdown(records, {"w"}, {"fd", "ours"});
  EXPECT_NE(table1.find("| w | fd | 0 |"), std::string::npos) << table1;
  EXPECT_NE(table1.find("| w | ours | 2 | 2.000 ± 1.414 |"), std::string::npos) << table1;
  EXPECT_NE(table1.find("0.600 ± 0.141"), std::string::npos) << table1;  // coverage
  // Mean curve 60, 90, 75, 70: max 90, min 60, diff 30, %R 33.3; per run 25 ± 7.1.
  const std::string table2 = Table2Markdown(records, curves, {"w"}, {"ours"});
  EXPECT_NE(table2.find("| w | ours | 2 | 90.0 & 60.0 | 30.0 | 33.3 | 25.0 ± 7.1 |"),
            std::string::npos)
      << table2;

  const std::string csv = RunsCsv(records);
  EXPECT_EQ(CountLines(csv), 3);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "world_label,run_dir,coverage,algebraic_connectivity,d_opt_reduction_percent,ssim");
}

// Coverage at a sixth, a third, two thirds and all of the duration, and the
// median time to 90 % with never-reached runs counted as the latest.
TEST(BenchReportTest, CoverageTableFromKnownRuns) {
  const std::string dir = FreshTestTempDir("coverage");
  std::vector<RunRecord> records;
  // (method, seed, time to 90 % or null, coverage series for seconds 1..6)
  const struct {
    const char* method;
    const char* time_to_90;
    const char* coverage_csv;
  } runs[] = {
      {"ours", "3.0", "t_s,coverage\n1,0.2\n2,0.5\n3,0.9\n4,0.9\n5,0.95\n6,0.95\n"},
      {"ours", "null", "t_s,coverage\n1,0.0\n2,0.3\n3,0.5\n4,0.6\n5,0.7\n6,0.8\n"},
      {"ours", "5.0",
       "t_s,coverage\n1,0.1\n2,0.4\n3,0.6\n4,0.7\n5,0.9\n"},  // done at 5 s: holds 0.9
      {"fd", "4.0", "t_s,coverage\n1,0.5\n2,0.6\n3,0.7\n4,0.9\n5,0.9\n6,0.9\n"},
      {"fd", "null", "t_s,coverage\n1,0.5\n2,0.6\n3,0.7\n4,0.8\n5,0.8\n6,0.8\n"},
  };
  int seed = 0;
  for (const auto& spec : runs) {
    RunRecord r;
    r.run = {"w", "w", spec.method, ++seed, dir + "/run_" + std::to_string(seed), "", ""};
    r.fields = {{"time_to_90_coverage_s", spec.time_to_90}};
    WriteFile(r.run.dir + "/coverage.csv", spec.coverage_csv);
    WriteFile(r.run.dir + "/uncertainty.csv", "t_s,mean_edge_d_opt\n");
    records.push_back(r);
  }
  const std::string table =
      CoverageMarkdown(records, ComputeCurves(records, 6.0), {"w"}, {"fd", "ours"}, 6.0);
  EXPECT_NE(
      table.find(
          "| coverage % at 1 s | coverage % at 2 s | coverage % at 4 s | coverage % at 6 s |"),
      std::string::npos)
      << table;
  // ours at 1, 2, 4, 6 s: means 10, 40, 73.3, 88.3 %; sorted times 3, 5, never: median 5 s.
  EXPECT_NE(table.find("| w | ours | 3 | 10.0 ± 10.0 | 40.0 ± 10.0 | 73.3 ± 15.3 | 88.3 ± 7.6 | 5 "
                       "s (2/3 reached) |"),
            std::string::npos)
      << table;
  // fd: times 4 and never; the median lies past the end.
  EXPECT_NE(table.find("| w | fd | 2 | 50.0 ± 0.0 | 60.0 ± 0.0 | 85.0 ± 7.1 | 85.0 ± 7.1 | > 6 s "
                       "(1/2 reached) |"),
            std::string::npos)
      << table;
}

TEST(BenchReportTest, ComparisonAgainstTheReferenceMethod) {
  std::vector<RunRecord> records;
  const struct {
    const char* method;
    const char* coverage;
    const char* time_to_90;
  } runs[] = {{"ours", "0.9", "3"}, {"ours", "0.8", "5"},  {"ours", "1.0", "null"},
              {"fd", "0.5", "4"},   {"fd", "0.6", "null"}, {"fd", "0.7", "null"}};
  int seed = 0;
  for (const auto& spec : runs) {
    RunRecord r;
    r.run = {"w", "w", spec.method, ++seed, "unused", "", ""};
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
  EXPECT_NE(table.find("| w | time to 90 % coverage (median) | > 6 s | 5 s | – (p = 0.64) |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| w | A.C | – | – | – |"), std::string::npos) << table;  // no values at all
}

TEST(BenchReportTest, CostTableFromKnownRuns) {
  std::vector<RunRecord> records;
  // sim s per CPU s, first and last 300 s, slam and total CPU seconds.
  const struct {
    const char* method;
    const char* rate;
    const char* first;
    const char* last;
    const char* slam_s;
    const char* total_s;
  } runs[] = {{"ours", "20", "40", "20", "30", "90"},
              {"ours", "30", "50", "40", "10", "60"},
              {"ours", "25", "60", "30", "20", "60"},
              {"fd", "null", "null", "null", "null", "null"}};  // a process-mode run
  int seed = 0;
  for (const auto& spec : runs) {
    RunRecord r;
    r.run = {"w", "w", spec.method, ++seed, "unused", "", ""};
    r.fields = {{"sim_per_cpu", spec.rate},
                {"sim_per_cpu_first_300s", spec.first},
                {"sim_per_cpu_last_300s", spec.last},
                {"node_cpu_s.slam", spec.slam_s},
                {"node_cpu_s.total", spec.total_s}};
    records.push_back(r);
  }
  const std::string table = CostMarkdown(records, {"w"}, {"fd", "ours"});
  // Ratios 0.5, 0.8, 0.5: median 0.5; slam shares 33, 17, 33 %: median 33; 210 CPU s in all.
  EXPECT_NE(
      table.find("| w | ours | 3 | 25.0 | 50.0 | 30.0 | 0.50 | – | 33 | – | – | – | – | 210 |"),
      std::string::npos)
      << table;
  EXPECT_NE(table.find("| w | fd | 1 | – | – | – | – | – | – | – | – | – | – | 0 |"),
            std::string::npos)
      << table;
}

// A sweep's reports: each markdown file one section per setting holding only that setting's
// runs, a setting column in runs.csv and curves.csv, sweep.md's medians per setting.
TEST(BenchReportTest, SweepReportsAreGroupedBySetting) {
  BenchOptions options;
  options.worlds = {"test"};
  options.methods = {"fd"};
  options.seeds = 3;
  options.duration_s = 4.0;
  options.out_dir = FreshTestTempDir("sweep_reports");
  options.plots = false;
  options.sweep = {"utility.lambda=0.3,1.2"};
  const std::vector<BenchRun> runs = PlanBench(options);  // seed 1: 0.3, 1.2; seed 2: ...
  ASSERT_EQ(runs.size(), 6u);
  // lambda 0.3: three runs, coverage 0.2, 0.4, 0.9; lambda 1.2: one run, coverage 0.7.
  FakeFinishedRun(runs[0], {{"coverage", "0.2"}, {"ate_rmse_m", "0.1"}}, 0.2);
  FakeFinishedRun(runs[2], {{"coverage", "0.4"}, {"ate_rmse_m", "0.3"}}, 0.4);
  FakeFinishedRun(
      runs[4], {{"coverage", "0.9"}, {"ate_rmse_m", "0.2"}, {"time_to_90_coverage_s", "3"}}, 0.9);
  FakeFinishedRun(runs[1], {{"coverage", "0.7"}, {"time_to_90_coverage_s", "2"}}, 0.7);
  const std::vector<std::string> written = WriteBenchReports(options);
  EXPECT_NE(std::find(written.begin(), written.end(), "sweep.md"), written.end());

  const std::string table1 = ReadFile(options.out_dir + "/table1.md");
  const std::size_t low = table1.find("## utility.lambda=0.3\n");
  const std::size_t high = table1.find("## utility.lambda=1.2\n");
  ASSERT_NE(low, std::string::npos) << table1;
  ASSERT_NE(high, std::string::npos) << table1;
  EXPECT_LT(low, high);  // in the order given
  EXPECT_NE(table1.find("| test | fd | 3 |", low), std::string::npos) << table1;
  EXPECT_LT(table1.find("| test | fd | 3 |", low), high) << table1;
  EXPECT_NE(table1.find("| test | fd | 1 |", high), std::string::npos) << table1;
  for (const std::string name : {"table2.md", "coverage.md", "comparison.md"}) {
    const std::string text = ReadFile(options.out_dir + "/" + name);
    EXPECT_LT(text.find("## utility.lambda=0.3\n"), text.find("## utility.lambda=1.2\n")) << name;
  }
  // coverage.md: at 4 s, lambda 0.3's three runs average 50 %, lambda 1.2's one is 70 %.
  const std::string coverage = ReadFile(options.out_dir + "/coverage.md");
  EXPECT_NE(coverage.find("| 50.0 ± 36.1 |"), std::string::npos) << coverage;
  EXPECT_GT(coverage.find("| 70.0 ± 0.0 |"), coverage.find("## utility.lambda=1.2")) << coverage;

  const std::string csv = ReadFile(options.out_dir + "/runs.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')).rfind("setting,world_label,run_dir,", 0), 0u) << csv;
  EXPECT_EQ(CountLines(csv), 5);
  EXPECT_NE(csv.find("\nutility.lambda=1.2,test," + runs[1].dir + ","), std::string::npos) << csv;
  const std::string curves = ReadFile(options.out_dir + "/curves.csv");
  EXPECT_EQ(curves.rfind("setting,world,method,t_s,", 0), 0u);
  EXPECT_NE(curves.find("\nutility.lambda=1.2,test,fd,4,1,0.7,"), std::string::npos) << curves;

  // Medians: coverage 0.4 and 0.7, time to 90 % never-never-3 s -> > 4 s, and 2 s.
  const std::string sweep = ReadFile(options.out_dir + "/sweep.md");
  EXPECT_NE(sweep.find("| test | fd | utility.lambda=0.3 | 3 | 0.400 | > 4 s | 0.200 | – |"),
            std::string::npos)
      << sweep;
  EXPECT_NE(sweep.find("| test | fd | utility.lambda=1.2 | 1 | 0.700 | 2 s | – | – |"),
            std::string::npos)
      << sweep;
  // Fig. 5's inputs per setting, in the setting's folder.
  EXPECT_TRUE(fs::exists(options.out_dir + "/settings/utility.lambda=1.2/fig5_test_extent.csv"));
  EXPECT_FALSE(fs::exists(options.out_dir + "/fig5_test_extent.csv"));
}

// Without --set the reports are the plain bench's: no sections, no setting column, no sweep.md.
TEST(BenchReportTest, NoSweepKeepsThePlainReports) {
  BenchOptions options;
  options.worlds = {"test"};
  options.methods = {"fd"};
  options.seeds = 1;
  options.duration_s = 4.0;
  options.out_dir = FreshTestTempDir("plain_reports");
  options.plots = false;
  FakeFinishedRun(PlanBench(options)[0], {{"coverage", "0.5"}});
  WriteBenchReports(options);
  EXPECT_EQ(ReadFile(options.out_dir + "/table1.md").rfind("| world | method | runs |", 0), 0u);
  EXPECT_EQ(ReadFile(options.out_dir + "/runs.csv").rfind("world_label,run_dir,", 0), 0u);
  EXPECT_EQ(ReadFile(options.out_dir + "/curves.csv").rfind("world,method,", 0), 0u);
  EXPECT_FALSE(fs::exists(options.out_dir + "/sweep.md"));
  EXPECT_TRUE(fs::exists(options.out_dir + "/fig5_test_extent.csv"));
}

}  // namespace
}  // namespace aslam
