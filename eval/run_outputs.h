#pragma once

// The run folder of `aslam explore`: map.yaml + map.pgm (ROS map_server),
// map.png (the map with pose graph, path and frontiers drawn over it),
// graph.g2o, coverage.csv (t_s,coverage), uncertainty.csv (t_s,mean_edge_d_opt),
// goals.csv (every goal and how it ended), cost.csv (in-process runs: CPU per node over simulated
// time) and metrics.json.

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "eval/explore_runner.h"

namespace aslam {

// metrics.json's text: one JSON object, keys in a fixed order, one per line;
// a missing time_to_90_coverage_s is null. Same metrics, same text.
std::string MetricsToJson(const RunMetrics& metrics);

// cost.csv's text: a header, then per sample t_s, wall_s and the cumulative
// CPU seconds of each node and in total.
std::string CostToCsv(const std::vector<CostSample>& samples);

// goals.csv's text: a header, then one row per goal in the order chosen; ended_at_s and
// path_length_at_choice_m are empty when unknown (an open goal, scores not heard).
std::string GoalsToCsv(const std::vector<GoalRecord>& goals);

// coverage.csv's text: a `t_s,coverage` header, then one row per sample.
std::string CoverageToCsv(const std::vector<CoverageSample>& samples);

// uncertainty.csv's text: a `t_s,mean_edge_d_opt` header, then one row per
// sample; the value is empty while the graph has no edge.
std::string UncertaintyToCsv(const std::vector<UncertaintySample>& samples);

// The first sample time at which coverage reaches `fraction`; nullopt if never.
std::optional<double> TimeToCoverage(const std::vector<CoverageSample>& samples, double fraction);

// map.png's image (BGR): the SLAM map in grey (free white, occupied black,
// unknown grey), scaled up `scale` times, with the SLAM path (light blue),
// odometry edges (blue), loop closures (red), keyframes, remaining
// frontiers (green dots) and the final pose (orange) drawn over it.
// scale 0 picks one that makes the image about 2000 px wide at most.
cv::Mat RenderRunImage(const ExploreResult& result, int scale = 0);

// Writes every file above into `dir` (created). Throws std::runtime_error
// naming the file that cannot be written.
void WriteRunFolder(const ExploreResult& result, const std::string& dir);

}  // namespace aslam
