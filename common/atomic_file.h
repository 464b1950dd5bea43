#pragma once

// Writing a file so that a crash, a kill or a full disk leaves either the old
// file or the whole new one, never a truncated mix: the run and bench folders'
// files (metrics.json, maps, graphs, tables) are written this way.

#include <string>
#include <string_view>

namespace aslam {

// Writes `contents` to a new temporary file in `path`'s folder, fsyncs it,
// renames it over `path` and fsyncs the folder. On failure the temporary file
// is removed, `path` keeps its old content (or stays absent) and
// std::runtime_error names `path` and the errno text. The file gets mode 0644.
void WriteFileAtomically(const std::string& path, std::string_view contents);

}  // namespace aslam
