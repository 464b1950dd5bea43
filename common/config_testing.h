#pragma once

// Shared by the config tests of every component (test targets define ASLAM_SOURCE_DIR).

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/config.h"
#include "common/test_temp_dir.h"

namespace aslam {

inline std::string ShippedConfigPath() {
  return std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml";
}

// Writes `yaml` to a file named `name` in the test case's own folder; returns its path.
inline std::string WriteTestConfig(const std::string& name, const std::string& yaml) {
  const std::string path = TestTempPath(name);
  std::ofstream(path) << yaml;
  return path;
}

// The ConfigError message that `load()` throws; "" when it loads.
template <typename Load>
std::string ConfigErrorOf(Load load) {
  try {
    load();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

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
