#include "frontier/frontier_config.h"

#include <stdexcept>

namespace aslam {

FrontierOptions LoadFrontierOptions(const ConfigReader& c, const NavOptions& nav) {
  FrontierOptions o;
  o.costmap = nav.costmap;
  o.global_planner = nav.global_planner;
  c.ReadInRange("free_threshold", &o.free_threshold, 0, 99);
  c.ReadInRange("min_size_m", &o.min_size_m, 0.0, 100.0);
  c.ReadInRange("max_segment_length_m", &o.max_segment_length_m, 0.05, 1000.0);
  c.ReadInRange("target_radius_m", &o.target_radius_m, 0.0, 100.0);
  c.ReadInRange("target_clearance_m", &o.target_clearance_m, 0.0, 10.0);
  c.ReadInRange("match_distance_m", &o.match_distance_m, 0.0, 100.0);
  c.CheckAllKeysUsed();

  if (o.free_threshold >= o.costmap.occupied_threshold) {
    c.Fail("free_threshold", "must be below nav.costmap.occupied_threshold = " +
                                 std::to_string(o.costmap.occupied_threshold));
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
  const NavOptions nav = LoadNavOptionsFromFile(file);
  return LoadFrontierOptions(ConfigReader::FromOptionalFile(file, "frontier"), nav);
}

}  // namespace aslam
