#include "eval/run_outputs.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "common/map_io.h"
#include "common/test_temp_dir.h"
#include "slam/g2o_io.h"

namespace aslam {
namespace {

RunMetrics SampleMetrics() {
  RunMetrics m;
  m.world = "worlds/\"odd\" name\\x";
  m.method = "ours";
  m.seed = 7;
  m.sim_seconds = 234.5;
  m.wall_seconds = 5.25;
  m.coverage = 0.987654321;
  m.ate_rmse_m = 0.0421;
  m.keyframes = 345;
  m.loop_closures = 6;
  m.collisions = 0;
  m.goals_reached = 12;
  m.goals_failed = 1;
  m.done = true;
  m.time_to_90_coverage_s = 120.0;
  m.end_reason = "done";
  return m;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(MetricsJsonTest, ParsesBackWithEveryRequiredField) {
  const RunMetrics m = SampleMetrics();
  const YAML::Node json = YAML::Load(MetricsToJson(m));  // JSON is YAML 1.2 flow
  ASSERT_TRUE(json.IsMap());
  for (const char* key : {"world", "method", "seed", "sim_seconds", "wall_seconds", "coverage",
                          "ate_rmse_m", "keyframes", "loop_closures", "collisions", "goals_reached",
                          "goals_failed", "done", "time_to_90_coverage_s"}) {
    EXPECT_TRUE(json[key].IsDefined()) << key;
  }
  EXPECT_EQ(json["world"].as<std::string>(), m.world);
  EXPECT_EQ(json["method"].as<std::string>(), "ours");
  EXPECT_EQ(json["seed"].as<int>(), 7);
  EXPECT_DOUBLE_EQ(json["sim_seconds"].as<double>(), 234.5);
  EXPECT_NEAR(json["coverage"].as<double>(), 0.987654321, 1e-9);
  EXPECT_NEAR(json["ate_rmse_m"].as<double>(), 0.0421, 1e-12);
  EXPECT_EQ(json["keyframes"].as<int>(), 345);
  EXPECT_EQ(json["loop_closures"].as<int>(), 6);
  EXPECT_EQ(json["collisions"].as<int>(), 0);
  EXPECT_EQ(json["goals_reached"].as<int>(), 12);
  EXPECT_EQ(json["goals_failed"].as<int>(), 1);
  EXPECT_TRUE(json["done"].as<bool>());
  EXPECT_DOUBLE_EQ(json["time_to_90_coverage_s"].as<double>(), 120.0);
}

TEST(MetricsJsonTest, MissingAndNonFiniteValuesAreNull) {
  RunMetrics m = SampleMetrics();
  m.time_to_90_coverage_s.reset();
  m.ate_rmse_m = std::numeric_limits<double>::quiet_NaN();
  m.done = false;
  const std::string text = MetricsToJson(m);
  EXPECT_NE(text.find("\"time_to_90_coverage_s\": null"), std::string::npos) << text;
  EXPECT_NE(text.find("\"ate_rmse_m\": null"), std::string::npos) << text;
  EXPECT_NE(text.find("\"done\": false"), std::string::npos) << text;
  EXPECT_EQ(text.find("nan"), std::string::npos);
}

TEST(MetricsJsonTest, ScanTimingOnlyFromDevicesRuns) {
  RunMetrics m = SampleMetrics();
  YAML::Node json = YAML::Load(MetricsToJson(m));  // not a devices run
  EXPECT_TRUE(json["scan_stamp_late_ms"].IsNull());
  EXPECT_TRUE(json["scan_timing_scans"].IsNull());
  ScanTiming timing;
  timing.scans = 0;  // a devices run without a scan taken turning
  m.scan_timing = timing;
  json = YAML::Load(MetricsToJson(m));
  EXPECT_TRUE(json["scan_stamp_late_ms"].IsNull());
  EXPECT_EQ(json["scan_timing_scans"].as<int>(), 0);
  timing.scans = 42;
  timing.median_ms = -1.5;
  timing.p10_ms = -4.0;
  timing.p90_ms = 3.0;
  m.scan_timing = timing;
  json = YAML::Load(MetricsToJson(m));
  EXPECT_DOUBLE_EQ(json["scan_stamp_late_ms"].as<double>(), -1.5);
  EXPECT_DOUBLE_EQ(json["scan_stamp_late_p10_ms"].as<double>(), -4.0);
  EXPECT_DOUBLE_EQ(json["scan_stamp_late_p90_ms"].as<double>(), 3.0);
  EXPECT_EQ(json["scan_timing_scans"].as<int>(), 42);
}

TEST(MetricsJsonTest, NodeCpuIsAnObjectWithTheTotal) {
  RunMetrics m = SampleMetrics();
  EXPECT_TRUE(YAML::Load(MetricsToJson(m))["node_cpu_s"].IsNull());  // process mode
  NodeCpu cpu;
  cpu.sim_s = 0.5;
  cpu.slam_s = 2.0;
  cpu.frontier_s = 1.0;
  cpu.utility_s = 0.75;
  cpu.nav_s = 1.25;
  cpu.evaluation_s = 0.25;
  cpu.other_s = 0.125;
  m.node_cpu = cpu;
  m.sim_per_cpu = 31.0;
  const YAML::Node json = YAML::Load(MetricsToJson(m));
  const YAML::Node nodes = json["node_cpu_s"];
  ASSERT_TRUE(nodes.IsMap());
  EXPECT_DOUBLE_EQ(nodes["slam"].as<double>(), 2.0);
  EXPECT_DOUBLE_EQ(nodes["nav"].as<double>(), 1.25);
  EXPECT_DOUBLE_EQ(nodes["other"].as<double>(), 0.125);
  EXPECT_DOUBLE_EQ(nodes["total"].as<double>(), 5.875);
  EXPECT_DOUBLE_EQ(json["sim_per_cpu"].as<double>(), 31.0);
  EXPECT_TRUE(json["sim_per_cpu_last_300s"].IsNull());
}

TEST(CostCsvTest, OneRowPerSampleWithCumulativeTotals) {
  NodeCpu cpu;
  cpu.frontier_s = 0.5;
  cpu.utility_s = 0.25;
  const std::string text = CostToCsv({{0.0, 0.0, NodeCpu{}}, {10.0, 1.5, cpu}});
  std::istringstream lines(text);
  std::string header, first, second, extra;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_FALSE(std::getline(lines, extra));
  EXPECT_EQ(header.rfind("t_s,wall_s,sim_cpu_s,slam_cpu_s,frontier_cpu_s,", 0), 0u) << header;
  EXPECT_EQ(second, "10.000,1.500,0.0000,0.0000,0.5000,0.2500,0.0000,0.0000,0.0000,0.7500");
}

TEST(MetricsJsonTest, SameMetricsSameText) {
  EXPECT_EQ(MetricsToJson(SampleMetrics()), MetricsToJson(SampleMetrics()));
}

TEST(CoverageCsvTest, HeaderThenOneRowPerSample) {
  const std::string csv = CoverageToCsv({{1.0, 0.1}, {2.0, 0.25}, {2.5, 0.5}});
  EXPECT_EQ(csv, "t_s,coverage\n1.000,0.100000\n2.000,0.250000\n2.500,0.500000\n");
  EXPECT_EQ(CoverageToCsv({}), "t_s,coverage\n");
}

TEST(CoverageCsvTest, TimeToCoverageIsTheFirstSampleReachingIt) {
  const std::vector<CoverageSample> s = {{1.0, 0.5}, {2.0, 0.9}, {3.0, 0.85}, {4.0, 0.95}};
  EXPECT_EQ(TimeToCoverage(s, 0.9), 2.0);
  EXPECT_EQ(TimeToCoverage(s, 0.95), 4.0);
  EXPECT_FALSE(TimeToCoverage(s, 0.96).has_value());
  EXPECT_FALSE(TimeToCoverage({}, 0.5).has_value());
}

ExploreResult SmallResult() {
  ExploreResult r;
  r.metrics = SampleMetrics();
  r.coverage = {{1.0, 0.2}, {2.0, 0.4}};
  r.map = OccupancyGrid(40, 20, 0.05, {-1.0, -0.5}, OccupancyGrid::kUnknown);
  for (int col = 5; col < 35; ++col) {
    for (int row = 5; row < 15; ++row) r.map.at({col, row}) = col == 34 ? 100 : 0;
  }
  r.graph.nodes = {
      {0, 100000, {0.0, 0.0, 0.0}}, {1, 200000, {0.3, 0.0, 0.0}}, {2, 300000, {0.6, 0.1, 0.0}}};
  PoseGraphEdge e01{0, 1, EdgeKind::kOdometry, {0.3, 0.0, 0.0}};
  PoseGraphEdge e12{1, 2, EdgeKind::kOdometry, {0.3, 0.1, 0.0}};
  PoseGraphEdge e02{0, 2, EdgeKind::kLoopClosure, {0.6, 0.1, 0.0}};
  r.graph.edges = {e01, e12, e02};
  r.slam_path = {{0.0, 0.0, 0.0}, {0.3, 0.05, 0.0}, {0.6, 0.1, 0.3}};
  r.frontiers_m = {{{0.5, 0.2}, {0.55, 0.2}}};
  NodeCpu cpu;
  cpu.slam_s = 1.5;
  cpu.nav_s = 0.25;
  r.cost = {{0.0, 0.0, NodeCpu{}}, {10.0, 0.5, cpu}};
  r.metrics.node_cpu = cpu;
  return r;
}

TEST(RunImageTest, MapScaledUpAndFlippedWithDrawingsOverIt) {
  const ExploreResult r = SmallResult();
  const cv::Mat image = RenderRunImage(r, 3);
  ASSERT_EQ(image.cols, 120);
  ASSERT_EQ(image.rows, 60);
  ASSERT_EQ(image.type(), CV_8UC3);
  // Unknown corner stays grey; the occupied column (map col 34) is black.
  EXPECT_EQ(image.at<cv::Vec3b>(0, 0), cv::Vec3b(205, 205, 205));
  EXPECT_EQ(image.at<cv::Vec3b>((20 - 1 - 6) * 3 + 1, 34 * 3 + 1), cv::Vec3b(0, 0, 0));
  // Something coloured (not grey) was drawn.
  int coloured = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      coloured += p[0] != p[1] || p[1] != p[2];
    }
  }
  EXPECT_GT(coloured, 50);
}

TEST(RunFolderTest, WritesEveryFileReadableByItsReader) {
  const std::string dir = TestTempPath("run");
  std::filesystem::remove_all(dir);
  const ExploreResult r = SmallResult();
  WriteRunFolder(r, dir);
  for (const char* f :
       {"map.yaml", "map.pgm", "map.png", "graph.g2o", "coverage.csv", "metrics.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
  const LoadedMap map = LoadMap(dir + "/map.yaml");
  EXPECT_EQ(map.grid.width_cells(), 40);
  EXPECT_EQ(map.grid.height_cells(), 20);
  const PoseGraph graph = ReadG2o(dir + "/graph.g2o");
  EXPECT_EQ(graph.nodes.size(), 3u);
  EXPECT_EQ(graph.edges.size(), 3u);
  EXPECT_EQ(ReadFile(dir + "/coverage.csv"), CoverageToCsv(r.coverage));
  EXPECT_EQ(ReadFile(dir + "/metrics.json"), MetricsToJson(r.metrics));
  EXPECT_EQ(ReadFile(dir + "/cost.csv"), CostToCsv(r.cost));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aslam
