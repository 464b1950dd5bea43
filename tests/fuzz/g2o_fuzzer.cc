// libFuzzer: arbitrary text as a g2o graph through ReadG2o. A std::exception naming the
// line is the expected answer to bad input.

#include <cstddef>
#include <cstdint>
#include <exception>

#include "slam/g2o_io.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string path = aslam::WriteFuzzInput(data, size, ".g2o");
  try {
    (void)aslam::ReadG2o(path);
  } catch (const std::exception&) {
  }
  return 0;
}
