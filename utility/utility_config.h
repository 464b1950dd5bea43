#pragma once

// The utility's options (one struct for the whole aslam-utility component)
// and the loader of the `utility:` config section, validated once at load time.

#include <string>

#include "common/config.h"
#include "utility/goal_selector.h"

namespace aslam {

struct UtilityOptions {
  GoalSelectorOptions selector;
  // No eligible frontier for this long (message time) and EXPLORE_STATUS says done.
  double done_timeout_s = 10.0;
};

// Reads and validates the `utility` section; throws ConfigError naming file, key and value.
UtilityOptions LoadUtilityOptions(const ConfigReader& utility_section);
// Convenience: the `utility` section of `file`; "" gives the defaults.
UtilityOptions LoadUtilityOptionsFromFile(const std::string& file);

}  // namespace aslam
