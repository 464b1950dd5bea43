#include "slam/slam_config.h"

#include <cmath>
#include <stdexcept>

#include "slam/slam.h"

namespace aslam {
namespace {

void LoadWindow(const ConfigReader& c, double max_linear_m, SearchWindow* w) {
  c.ReadInRange("linear_m", &w->linear_m, 0.01, max_linear_m);
  c.ReadInRange("angular_rad", &w->angular_rad, 0.001, M_PI);
}

void LoadKeyframe(const ConfigReader& c, KeyframeOptions* o) {
  c.ReadInRange("travel_m", &o->travel_m, 0.01, 100.0);
  c.ReadInRange("rotation_rad", &o->rotation_rad, 0.01, 2.0 * M_PI);
}

void LoadMapThinning(const ConfigReader& c, MapThinningOptions* o) {
  c.Read("enabled", &o->enabled);
  c.ReadInRange("max_revealed_area_m2", &o->max_revealed_area_m2, 0.0, 1e6);
  c.ReadInRange("max_travel_m", &o->max_travel_m, 0.0, 100.0);
  c.ReadInRange("max_rotation_rad", &o->max_rotation_rad, 0.0, 2.0 * M_PI);
}

void LoadFrontEnd(const ConfigReader& c, FrontEndOptions* o) {
  c.ReadInRange("point_spacing_m", &o->point_spacing_m, 0.0, 1.0);
  c.ReadInRange("local_map_keyframes", &o->local_map_keyframes, 1, 1000);
  LoadWindow(c.Section("window"), 10.0, &o->window);
  c.ReadInRange("min_response", &o->min_response, 0.0, 1.0);
  c.ReadInRange("odometry_sigma_m", &o->odometry_sigma_m, 1e-4, 10.0);
  c.ReadInRange("odometry_sigma_rad", &o->odometry_sigma_rad, 1e-5, M_PI);
}

void LoadLoopClosure(const ConfigReader& c, LoopClosureOptions* o) {
  c.Read("enabled", &o->enabled);
  c.ReadInRange("search_radius_m", &o->search_radius_m, 0.1, 100.0);
  c.ReadInRange("recent_chain_keyframes", &o->recent_chain_keyframes, 1, 1000000);
  c.ReadInRange("neighbour_keyframes", &o->neighbour_keyframes, 0, 1000);
  LoadWindow(c.Section("window"), 20.0, &o->window);
  c.ReadInRange("min_response", &o->min_response, 0.0, 1.0);
  c.ReadInRange("keyframes_between_attempts", &o->keyframes_between_attempts, 1, 1000000);
  c.ReadInRange("max_chi_square", &o->max_chi_square, 1e-3, 1e9);
  c.ReadInRange("map_rerender_tolerance_m", &o->map_rerender_tolerance_m, 0.0, 10.0);
}

void LoadScanMatcher(const ConfigReader& c, ScanMatcherOptions* o) {
  c.ReadInRange("resolution_m", &o->resolution_m, 0.005, 1.0);
  c.ReadInRange("smear_sigma_m", &o->smear_sigma_m, 0.001, 1.0);
  c.ReadInRange("coarse_factor", &o->coarse_factor, 2, 16);
  c.ReadInRange("coarse_levels", &o->coarse_levels, 0, 10);
  c.ReadInRange("angular_step_rad", &o->angular_step_rad, 0.0, 0.5);
  c.ReadInRange("max_point_range_m", &o->max_point_range_m, 0.1, 1000.0);
  c.ReadInRange("window_edge_penalty", &o->window_edge_penalty, 0.0, 1.0);
  c.ReadInRange("covariance_response_gain", &o->covariance_response_gain, 0.0, 1e6);
  c.ReadInRange("covariance_radius_m", &o->covariance_radius_m, 0.0, 10.0);
  c.ReadInRange("covariance_radius_rad", &o->covariance_radius_rad, 0.0, M_PI);
  c.ReadInRange("min_stddev_m", &o->min_stddev_m, 1e-4, 10.0);
  c.ReadInRange("min_stddev_rad", &o->min_stddev_rad, 1e-5, M_PI);
}

void LoadOptimizer(const ConfigReader& c, PoseGraphOptimizerOptions* o) {
  c.ReadInRange("max_iterations", &o->max_iterations, 1, 100000);
  c.ReadInRange("function_tolerance", &o->function_tolerance, 1e-16, 1.0);
  c.ReadInRange("loop_closure_loss_scale", &o->loop_closure_loss_scale, 0.0, 1e6);
  c.ReadInRange("num_threads", &o->num_threads, 1, 256);
}

void LoadMapper(const ConfigReader& c, OccupancyMapperOptions* o) {
  c.ReadInRange("resolution_m", &o->resolution_m, 0.005, 1.0);
  c.ReadInRange("log_odds_hit", &o->log_odds_hit, 1e-3, 50.0);
  c.ReadInRange("log_odds_miss", &o->log_odds_miss, -50.0, -1e-3);
  c.ReadInRange("log_odds_min", &o->log_odds_min, -100.0, -1e-3);
  c.ReadInRange("log_odds_max", &o->log_odds_max, 1e-3, 100.0);
  c.ReadInRange("no_return_clear_m", &o->no_return_clear_m, 0.0, 100.0);
  c.ReadInRange("growth_margin_m", &o->growth_margin_m, 0.0, 100.0);
  c.ReadInRange("free_threshold", &o->free_threshold, 0.001, 0.499);
  c.ReadInRange("occupied_threshold", &o->occupied_threshold, 0.501, 0.999);
  c.ReadInRange("submap_keyframes", &o->submap_keyframes, 1, 100000);
}

void LoadInput(const ConfigReader& c, InputOptions* o) {
  c.ReadInRange("min_valid_points", &o->min_valid_points, 3, 1000000);
  c.ReadInRange("max_linear_speed_mps", &o->max_linear_speed_mps, 0.01, 100.0);
  c.ReadInRange("max_angular_speed_radps", &o->max_angular_speed_radps, 0.01, 100.0);
  c.ReadInRange("odometry_buffer_s", &o->odometry_buffer_s, 0.1, 3600.0);
  c.ReadInRange("max_time_gap_s", &o->max_time_gap_s, 0.05, 3600.0);
  c.ReadInRange("resync_messages", &o->resync_messages, 2, 100);
  c.Read("deskew", &o->deskew);
  c.ReadInRange("deskew_max_extrapolation_s", &o->deskew_max_extrapolation_s, 0.0, 1.0);
}

void LoadNode(const ConfigReader& c, SlamNodeOptions* o) {
  c.ReadInRange("map_period_s", &o->map_period_s, 0.0, 3600.0);
  c.ReadInRange("republish_period_s", &o->republish_period_s, 0.1, 3600.0);
  std::string encoding = o->map_encoding == SlamNodeOptions::MapEncoding::kRaw ? "raw" : "zlib";
  c.Read("map_encoding", &encoding);
  if (encoding == "zlib") {
    o->map_encoding = SlamNodeOptions::MapEncoding::kZlib;
  } else if (encoding == "raw") {
    o->map_encoding = SlamNodeOptions::MapEncoding::kRaw;
  } else {
    c.Fail("map_encoding", "must be zlib or raw");
  }
}

// The library's own checks, reported against the file and section.
template <typename Validate>
void Check(const ConfigReader& slam, const std::string& section, Validate validate) {
  try {
    validate();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(slam.file() + ": section " + section + ": " + e.what());
  }
}

}  // namespace

SlamConfig LoadSlamConfig(const ConfigReader& slam) {
  SlamConfig config;
  SlamOptions& o = config.slam;
  LoadKeyframe(slam.Section("keyframe"), &o.keyframe);
  LoadMapThinning(slam.Section("map_thinning"), &o.map_thinning);
  const ConfigReader front_end = slam.Section("front_end");
  LoadFrontEnd(front_end, &o.front_end);
  const ConfigReader loop_closure = slam.Section("loop_closure");
  LoadLoopClosure(loop_closure, &o.loop_closure);
  LoadScanMatcher(slam.Section("scan_matcher"), &o.scan_matcher);
  LoadOptimizer(slam.Section("optimizer"), &o.optimizer);
  LoadMapper(slam.Section("mapper"), &o.mapper);
  LoadInput(slam.Section("input"), &o.input);
  LoadNode(slam.Section("node"), &config.node);
  slam.CheckAllKeysUsed();

  // Keyframes already in the sequential local map would make "loop closures"
  // that close nothing.
  if (o.loop_closure.recent_chain_keyframes < o.front_end.local_map_keyframes) {
    loop_closure.Fail("recent_chain_keyframes",
                      "must be at least front_end.local_map_keyframes = " +
                          std::to_string(o.front_end.local_map_keyframes));
  }
  Check(slam, slam.KeyPath("scan_matcher"), [&] { ValidateScanMatcherOptions(o.scan_matcher); });
  Check(slam, "slam", [&] { ValidateSlamOptions(o); });
  return config;
}

SlamConfig LoadSlamConfigFromFile(const std::string& file) {
  if (file.empty()) return SlamConfig{};
  return LoadSlamConfig(ConfigReader::FromFile(file, "slam"));
}

SlamOptions LoadSlamOptions(const ConfigReader& slam_section) {
  return LoadSlamConfig(slam_section).slam;
}

SlamOptions LoadSlamOptionsFromFile(const std::string& file) {
  return LoadSlamConfigFromFile(file).slam;
}

}  // namespace aslam
