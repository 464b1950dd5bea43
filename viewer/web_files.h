#pragma once

// The page's files (viewer/web/), built into the binary by viewer/embed_web_files.cmake so
// that aslam-viewer runs from anywhere with nothing beside it.

#include <cstddef>

namespace aslam {

struct WebFile {
  const char* path;  // as requested: "/index.html", "/viewer.js", ...
  const char* mime_type;
  const unsigned char* data;
  std::size_t size;
};

extern const WebFile kWebFiles[];
extern const std::size_t kWebFileCount;

}  // namespace aslam
