#pragma once

// Shared by the config tests of every component (test targets define ASLAM_SOURCE_DIR).

#include <string>

#include "common/config.h"

namespace aslam {

inline std::string ShippedConfigPath() { return std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml"; }

// The ConfigError message that loading `section` of `yaml` (named test.yaml)
// with `load` throws; "" when it loads.
template <typename Load>
std::string ConfigErrorOf(Load load, const std::string& yaml, const std::string& section) {
  try {
    load(ConfigReader::FromString(yaml, section, "test.yaml"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace aslam
