// libFuzzer: arbitrary text as a map_server map.yaml (its image a fixed small PGM beside it)
// through LoadMap. A std::exception naming the problem is the expected answer to bad input.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <fstream>

#include "common/map_io.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace aslam;
  static const bool image_written = [] {
    // 4 x 3 cells: free, occupied and unknown grey levels; beside the input, as it names it.
    std::ofstream(FuzzFilePath("aslam_fuzz_map.pgm"), std::ios::binary)
        << "P5\n4 3\n255\n"
        << std::string("\xfe\x00\xcd\xfe\xfe\x00\xcd\xfe\xfe\x00\xcd\xfe", 12);
    return true;
  }();
  (void)image_written;
  const std::string path = WriteFuzzInput(data, size, ".yaml");
  try {
    (void)LoadMap(path);
  } catch (const std::exception&) {
  }
  return 0;
}
