// libFuzzer: arbitrary text as config/aslam.yaml through every component's loader. A
// ConfigError (or another std::exception naming the problem) is the expected answer to bad
// input; a crash, a leak or undefined behaviour is a finding.

#include <cstddef>
#include <cstdint>
#include <exception>

#include "frontier/frontier_config.h"
#include "navigation/nav_config.h"
#include "slam/slam_config.h"
#include "tests/fuzz/fuzz_input_file.h"
#include "utility/utility_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace aslam;
  const std::string path = WriteFuzzInput(data, size, ".yaml");
  auto expect_clean_failure = [](auto&& load) {
    try {
      load();
    } catch (const std::exception&) {
    }
  };
  expect_clean_failure([&] { (void)LoadSlamConfigFromFile(path); });
  expect_clean_failure([&] { (void)LoadNavOptionsFromFile(path); });
  expect_clean_failure([&] { (void)LoadFrontierOptionsFromFile(path); });
  expect_clean_failure([&] { (void)LoadUtilityOptionsFromFile(path); });
  return 0;
}
