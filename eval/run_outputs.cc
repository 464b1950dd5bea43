#include "eval/run_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/atomic_file.h"
#include "common/json_text.h"
#include "common/map_io.h"
#include "common/text_format.h"
#include "slam/g2o_io.h"

namespace aslam {
namespace {

std::string OptionalNumber(const std::optional<double>& value) {
  return value ? JsonNumber(*value) : "null";
}

std::string NodeCpuJson(const NodeCpu& cpu) {
  return JsonObject({{"sim", JsonNumber(cpu.sim_s)},
                     {"slam", JsonNumber(cpu.slam_s)},
                     {"frontier", JsonNumber(cpu.frontier_s)},
                     {"utility", JsonNumber(cpu.utility_s)},
                     {"nav", JsonNumber(cpu.nav_s)},
                     {"evaluation", JsonNumber(cpu.evaluation_s)},
                     {"other", JsonNumber(cpu.other_s)},
                     {"total", JsonNumber(cpu.total_s())}});
}

std::string CountsJson(const std::vector<std::pair<std::string, int>>& counts) {
  std::vector<std::pair<std::string, std::string>> fields;
  for (const auto& [name, count] : counts) fields.emplace_back(name, std::to_string(count));
  return JsonObject(fields);
}

std::string FailuresJson(const std::vector<std::pair<std::string, int>>& by_reason) {
  std::string out = "[";
  for (std::size_t i = 0; i < by_reason.size(); ++i) {
    out += (i ? ", " : "") + JsonObject({{"reason", JsonString(by_reason[i].first)},
                                         {"goals", std::to_string(by_reason[i].second)}});
  }
  return out + "]";
}

std::string StuckJson(const std::vector<StuckEpisode>& episodes) {
  std::string out = "[";
  for (std::size_t i = 0; i < episodes.size(); ++i) {
    const StuckEpisode& e = episodes[i];
    out += (i ? ", " : "") + JsonObject({{"start_s", JsonNumber(e.start_s)},
                                         {"detected_s", JsonNumber(e.detected_s)},
                                         {"end_s", OptionalNumber(e.end_s)},
                                         {"x_m", JsonNumber(e.position_m.x_m)},
                                         {"y_m", JsonNumber(e.position_m.y_m)}});
  }
  return out + "]";
}

std::string OptionalCsvNumber(const std::optional<double>& value, const char* format) {
  return value ? Format(format, *value) : "";
}

}  // namespace

std::string MetricsToJson(const RunMetrics& m) {
  std::vector<std::pair<std::string, std::string>> fields = {
      {"world", JsonString(m.world)},
      {"method", JsonString(m.method)},
      {"seed", std::to_string(m.seed)},
      {"sim_seconds", JsonNumber(m.sim_seconds)},
      {"wall_seconds", JsonNumber(m.wall_seconds)},
      {"coverage", JsonNumber(m.coverage)},
      {"ate_rmse_m", JsonNumber(m.ate_rmse_m)},
      {"keyframes", std::to_string(m.keyframes)},
      {"loop_closures", std::to_string(m.loop_closures)},
      {"collisions", std::to_string(m.collisions)},
      {"goals_reached", std::to_string(m.goals_reached)},
      {"goals_failed", std::to_string(m.goals_failed)},
      {"done", m.done ? "true" : "false"},
      {"time_to_90_coverage_s", OptionalNumber(m.time_to_90_coverage_s)},
      {"end_reason", JsonString(m.end_reason)},
      {"decisions", std::to_string(m.decisions)},
      {"goal_outcomes", CountsJson(m.goal_outcomes)},
      {"goal_failures_by_reason", FailuresJson(m.goal_failures_by_reason)},
      {"stuck_episodes", std::to_string(m.stuck_episodes.size())},
      {"stuck_s", JsonNumber(m.stuck_s)},
      {"stuck", StuckJson(m.stuck_episodes)},
      {"ate_max_m", JsonNumber(m.ate_max_m)},
      {"ate_matched_keyframes", std::to_string(m.ate_matched)},
      {"free_area_m2", JsonNumber(m.free_area_m2)},
      {"map_occupied_precision", JsonNumber(m.occupied_precision)},
      {"map_free_precision", JsonNumber(m.free_precision)},
      {"average_degree", JsonNumber(m.average_degree)},
      {"algebraic_connectivity", JsonNumber(m.algebraic_connectivity)},
      {"normalized_tree_connectivity", JsonNumber(m.normalized_tree_connectivity)},
      {"ssim", JsonNumber(m.ssim)},
      {"map_rmse", JsonNumber(m.map_rmse)},
      {"mean_edge_d_opt", JsonNumber(m.mean_edge_d_opt)},
      {"d_opt_max", JsonNumber(m.d_opt_max)},
      {"d_opt_min", JsonNumber(m.d_opt_min)},
      {"d_opt_difference", JsonNumber(m.d_opt_difference)},
      {"d_opt_reduction_percent", JsonNumber(m.d_opt_reduction_percent)},
      // Devices runs only; NaN (no scan to fit) is null too.
      {"scan_stamp_late_ms", m.scan_timing ? JsonNumber(m.scan_timing->median_ms) : "null"},
      {"scan_stamp_late_p10_ms", m.scan_timing ? JsonNumber(m.scan_timing->p10_ms) : "null"},
      {"scan_stamp_late_p90_ms", m.scan_timing ? JsonNumber(m.scan_timing->p90_ms) : "null"},
      {"scan_timing_scans", m.scan_timing ? std::to_string(m.scan_timing->scans) : "null"},
      {"map_in_world_x_m", JsonNumber(m.map_in_world.x_m)},
      {"map_in_world_y_m", JsonNumber(m.map_in_world.y_m)},
      {"map_in_world_yaw_rad", JsonNumber(m.map_in_world.yaw_rad)},
      {"sim_per_cpu", OptionalNumber(m.sim_per_cpu)},
      {"sim_per_cpu_first_300s", OptionalNumber(m.sim_per_cpu_first_300s)},
      {"sim_per_cpu_last_300s", OptionalNumber(m.sim_per_cpu_last_300s)},
      {"node_cpu_s", m.node_cpu ? NodeCpuJson(*m.node_cpu) : "null"},
  };
  if (!m.processes.empty())
    fields.emplace_back("processes", ProcessHistoriesJson(m.processes, "  "));
  std::string out = "{\n";
  for (std::size_t i = 0; i < fields.size(); ++i) {
    out += "  " + JsonString(fields[i].first) + ": " + fields[i].second;
    out += i + 1 < fields.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

std::string CostToCsv(const std::vector<CostSample>& samples) {
  std::string out =
      "t_s,wall_s,sim_cpu_s,slam_cpu_s,frontier_cpu_s,utility_cpu_s,nav_cpu_s,"
      "evaluation_cpu_s,other_cpu_s,total_cpu_s\n";
  for (const CostSample& s : samples) {
    const NodeCpu& c = s.cpu;
    out += Format("%.3f,%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", s.t_s, s.wall_s, c.sim_s,
                  c.slam_s, c.frontier_s, c.utility_s, c.nav_s, c.evaluation_s, c.other_s,
                  c.total_s());
  }
  return out;
}

std::string GoalsToCsv(const std::vector<GoalRecord>& goals) {
  std::string out =
      "goal_id,frontier_id,target_x_m,target_y_m,chosen_at_s,ended_at_s,outcome,reason,"
      "path_length_at_choice_m,driven_m\n";
  for (const GoalRecord& g : goals) {
    out += Format("%lld,%d,%.3f,%.3f,%.3f,", static_cast<long long>(g.goal_id), g.frontier_id,
                  g.target_m.x_m, g.target_m.y_m, g.chosen_at_s);
    out += OptionalCsvNumber(g.ended_at_s, "%.3f") + "," + GoalOutcomeName(g.outcome) + "," +
           CsvField(g.reason) + "," + OptionalCsvNumber(g.path_length_at_choice_m, "%.3f") +
           Format(",%.3f\n", g.driven_m);
  }
  return out;
}

std::string CoverageToCsv(const std::vector<CoverageSample>& samples) {
  std::string out = "t_s,coverage\n";
  char buffer[64];
  for (const CoverageSample& s : samples) {
    std::snprintf(buffer, sizeof buffer, "%.3f,%.6f\n", s.t_s, s.coverage);
    out += buffer;
  }
  return out;
}

std::string UncertaintyToCsv(const std::vector<UncertaintySample>& samples) {
  std::string out = "t_s,mean_edge_d_opt\n";
  char buffer[64];
  for (const UncertaintySample& s : samples) {
    if (std::isfinite(s.mean_edge_d_opt)) {
      std::snprintf(buffer, sizeof buffer, "%.3f,%.6f\n", s.t_s, s.mean_edge_d_opt);
    } else {
      std::snprintf(buffer, sizeof buffer, "%.3f,\n", s.t_s);  // no edge yet
    }
    out += buffer;
  }
  return out;
}

std::optional<double> TimeToCoverage(const std::vector<CoverageSample>& samples, double fraction) {
  for (const CoverageSample& s : samples) {
    if (s.coverage >= fraction) return s.t_s;
  }
  return std::nullopt;
}

cv::Mat RenderRunImage(const ExploreResult& result, int scale) {
  const OccupancyGrid& map = result.map;
  if (map.empty()) return cv::Mat(1, 1, CV_8UC3, cv::Scalar(205, 205, 205));
  const int w = map.width_cells();
  const int h = map.height_cells();
  if (scale <= 0) scale = std::clamp(2000 / std::max(w, h), 1, 4);
  // map_saver's greys: free 254, occupied 0, unknown 205; in between by occupancy.
  cv::Mat grey(h, w, CV_8UC1);
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const int8_t v = map.at({col, row});
      const uint8_t g = v < 0 ? 205 : static_cast<uint8_t>(254 - (254 * v) / 100);
      grey.at<uint8_t>(h - 1 - row, col) = g;  // image row 0 is the map's top
    }
  }
  cv::Mat image;
  cv::cvtColor(grey, image, cv::COLOR_GRAY2BGR);
  cv::resize(image, image, cv::Size(w * scale, h * scale), 0, 0, cv::INTER_NEAREST);

  const double res = map.resolution_m();
  const Point2d origin = map.origin_m();
  constexpr int kShift = 4;  // sub-pixel bits for OpenCV's drawing
  auto pixel = [&](double x_m, double y_m) {
    const double px = (x_m - origin.x_m) / res * scale;
    const double py = (h - (y_m - origin.y_m) / res) * scale;
    return cv::Point(static_cast<int>(std::lround(px * (1 << kShift))),
                     static_cast<int>(std::lround(py * (1 << kShift))));
  };
  const int thin = std::max(1, scale / 2);

  for (std::size_t i = 1; i < result.slam_path.size(); ++i) {
    const Pose2d& a = result.slam_path[i - 1];
    const Pose2d& b = result.slam_path[i];
    cv::line(image, pixel(a.x_m, a.y_m), pixel(b.x_m, b.y_m), cv::Scalar(255, 200, 120), thin + 2,
             cv::LINE_AA, kShift);
  }
  const auto& nodes = result.graph.nodes;
  for (const PoseGraphEdge& e : result.graph.edges) {
    if (e.from_id < 0 || e.to_id < 0 || e.from_id >= static_cast<int>(nodes.size()) ||
        e.to_id >= static_cast<int>(nodes.size())) {
      continue;
    }
    const Pose2d& a = nodes[e.from_id].pose;
    const Pose2d& b = nodes[e.to_id].pose;
    const bool loop = e.kind == EdgeKind::kLoopClosure;
    cv::line(image, pixel(a.x_m, a.y_m), pixel(b.x_m, b.y_m),
             loop ? cv::Scalar(40, 40, 230) : cv::Scalar(180, 80, 0), loop ? thin + 1 : thin,
             cv::LINE_AA, kShift);
  }
  for (const PoseGraphNode& n : nodes) {
    cv::circle(image, pixel(n.pose.x_m, n.pose.y_m), (thin + 1) << kShift, cv::Scalar(120, 40, 0),
               cv::FILLED, cv::LINE_AA, kShift);
  }
  for (const auto& frontier : result.frontiers_m) {
    for (const Point2d& p : frontier) {
      cv::circle(image, pixel(p.x_m, p.y_m), (thin + 1) << kShift, cv::Scalar(40, 170, 40),
                 cv::FILLED, cv::LINE_AA, kShift);
    }
  }
  if (!result.slam_path.empty() || !nodes.empty()) {
    const Pose2d& end = result.slam_path.empty() ? nodes.back().pose : result.slam_path.back();
    const double arrow_m = 0.5;
    cv::circle(image, pixel(end.x_m, end.y_m), (3 * scale) << kShift, cv::Scalar(0, 140, 255),
               cv::FILLED, cv::LINE_AA, kShift);
    cv::line(
        image, pixel(end.x_m, end.y_m),
        pixel(end.x_m + arrow_m * std::cos(end.yaw_rad), end.y_m + arrow_m * std::sin(end.yaw_rad)),
        cv::Scalar(0, 140, 255), thin + 1, cv::LINE_AA, kShift);
  }
  return image;
}

void WriteRunFolder(const ExploreResult& result, const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir + ": " + error.message());
  if (!result.map.empty()) SaveMap(result.map, dir + "/map");
  WriteImageAtomically(dir + "/map.png", RenderRunImage(result));
  WriteG2o(result.graph, dir + "/graph.g2o");
  WriteFileAtomically(dir + "/coverage.csv", CoverageToCsv(result.coverage));
  WriteFileAtomically(dir + "/uncertainty.csv", UncertaintyToCsv(result.uncertainty));
  WriteFileAtomically(dir + "/goals.csv", GoalsToCsv(result.goals));
  if (!result.cost.empty()) WriteFileAtomically(dir + "/cost.csv", CostToCsv(result.cost));
  WriteFileAtomically(dir + "/metrics.json", MetricsToJson(result.metrics));
}

}  // namespace aslam
