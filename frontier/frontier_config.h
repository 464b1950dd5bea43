#pragma once

// The loader of the `frontier:` config section into FrontierOptions (one
// struct for the whole aslam-frontier component), validated once at load time.
// Traversability and reachability are the navigator's: the costmap (with the
// robot's radius and clearance margin) and the planner options come from the
// navigator's options, so "reachable" means the navigator will plan there.
// Inflation costs do not change which cells are reachable.

#include <string>

#include "common/config.h"
#include "frontier/frontier_extractor.h"
#include "navigation/nav_config.h"

namespace aslam {

// Reads and validates the `frontier` section, planning on `nav`'s costmap and
// global planner; throws ConfigError naming file, key and value.
FrontierOptions LoadFrontierOptions(const ConfigReader& frontier_section, const NavOptions& nav);
// Convenience: the `robot`, `nav` and `frontier` sections of `file`; "" gives the defaults.
FrontierOptions LoadFrontierOptionsFromFile(const std::string& file);

}  // namespace aslam
