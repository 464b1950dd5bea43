#pragma once

// File helpers shared by the bench's tests.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/map_io.h"
#include "eval/bench_runs.h"
#include "slam/g2o_io.h"

namespace aslam {

inline void WriteFile(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline int CountLines(const std::string& text) {
  int n = 0;
  for (const char c : text) n += c == '\n';
  return n;
}

// A finished run in run.dir as `aslam explore` leaves it, enough for every report: metrics.json
// with `fields` (JSON values as text, e.g. {"coverage", "0.5"}) and end_reason "duration",
// coverage.csv holding `coverage` and uncertainty.csv 1.0 for `seconds` s, a small unknown map
// and an empty pose graph.
inline void FakeFinishedRun(const BenchRun& run,
                            const std::vector<std::pair<std::string, std::string>>& fields,
                            double coverage = 0.5, int seconds = 4) {
  std::string json = "{\n  \"world\": \"" + run.world_label + "\",\n  \"method\": \"" + run.method +
                     "\",\n  \"seed\": " + std::to_string(run.seed) + ",\n";
  for (const auto& [key, value] : fields) json += "  \"" + key + "\": " + value + ",\n";
  WriteFile(run.dir + "/metrics.json", json +
                                           "  \"map_in_world_x_m\": 0,\n  \"map_in_world_y_m\": "
                                           "0,\n  \"map_in_world_yaw_rad\": 0,\n  "
                                           "\"end_reason\": \"duration\"\n}\n");
  std::string coverage_csv = "t_s,coverage\n", uncertainty_csv = "t_s,mean_edge_d_opt\n";
  for (int t = 1; t <= seconds; ++t) {
    coverage_csv += std::to_string(t) + "," + std::to_string(coverage) + "\n";
    uncertainty_csv += std::to_string(t) + ",1.0\n";
  }
  WriteFile(run.dir + "/coverage.csv", coverage_csv);
  WriteFile(run.dir + "/uncertainty.csv", uncertainty_csv);
  SaveMap(OccupancyGrid(10, 10, 0.05, {0.0, 0.0}), run.dir + "/map");
  WriteG2o(PoseGraph{}, run.dir + "/graph.g2o");
}

}  // namespace aslam
