#include "frontier/frontier_config.h"

#include <stdexcept>

namespace aslam {

FrontierOptions LoadFrontierOptions(const ConfigReader& c) {
  FrontierOptions o;
  c.ReadInRange("free_threshold", &o.free_threshold, 0, 99);
  c.ReadInRange("min_size_m", &o.min_size_m, 0.0, 100.0);
  c.ReadInRange("max_segment_length_m", &o.max_segment_length_m, 0.05, 1000.0);
  c.ReadInRange("target_radius_m", &o.target_radius_m, 0.0, 100.0);
  c.ReadInRange("match_distance_m", &o.match_distance_m, 0.0, 100.0);
  c.ReadInRange("robot_radius_m", &o.costmap.robot_radius_m, 0.01, 5.0);

  const ConfigReader costmap = c.Section("costmap");
  costmap.ReadInRange("clearance_margin_m", &o.costmap.clearance_margin_m, 0.0, 5.0);
  costmap.ReadInRange("occupied_threshold", &o.costmap.occupied_threshold, 1, 100);
  costmap.Read("unknown_passable", &o.costmap.unknown_passable);
  const ConfigReader planner = c.Section("global_planner");
  planner.ReadInRange("start_escape_m", &o.global_planner.start_escape_m, 0.0, 5.0);
  c.CheckAllKeysUsed();

  if (o.free_threshold >= o.costmap.occupied_threshold) {
    c.Fail("free_threshold", "must be below costmap.occupied_threshold");
  }
  if (o.max_segment_length_m < o.min_size_m) {
    c.Fail("max_segment_length_m", "must not be below min_size_m");
  }
  // The components' own checks, reported against the section.
  try {
    o.Validate();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(c.file() + ": section frontier: " + e.what());
  }
  return o;
}

FrontierOptions LoadFrontierOptionsFromFile(const std::string& file) {
  if (file.empty()) return FrontierOptions{};
  return LoadFrontierOptions(ConfigReader::FromFile(file, "frontier"));
}

}  // namespace aslam
