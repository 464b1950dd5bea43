#pragma once

// The loader of the `frontier:` config section into FrontierOptions (one
// struct for the whole aslam-frontier component), validated once at load time.
// Only the costmap and planner keys that decide traversability and
// reachability are read; costs (inflation, unknown_cost) do not matter here.

#include <string>

#include "common/config.h"
#include "frontier/frontier_extractor.h"

namespace aslam {

// Reads and validates the `frontier` section; throws ConfigError naming file, key and value.
FrontierOptions LoadFrontierOptions(const ConfigReader& frontier_section);
// Convenience: the `frontier` section of `file`; "" gives the defaults.
FrontierOptions LoadFrontierOptionsFromFile(const std::string& file);

}  // namespace aslam
