#pragma once

// The fuzzers' inputs written to a file, for loaders that read files.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace aslam {

// A file named `name` in the temp folder (TMPDIR: scripts/fuzz gives each run its own and
// removes it).
inline std::string FuzzFilePath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / name).string();
}

// A file of this process holding the input; rewritten for each input.
inline std::string WriteFuzzInput(const uint8_t* data, std::size_t size,
                                  const std::string& suffix) {
  const std::string path = FuzzFilePath("aslam_fuzz_" + std::to_string(::getpid()) + suffix);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace aslam
