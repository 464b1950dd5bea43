#pragma once

// What the viewer's tests share.

#include <string>

namespace aslam {

// The frame without the spaces JsonObject puts after ':' and ',' (strings keep theirs).
inline std::string Compact(const std::string& frame) {
  std::string out;
  bool in_string = false;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const char c = frame[i];
    if (c == '"' && (i == 0 || frame[i - 1] != '\\')) in_string = !in_string;
    if (!in_string && c == ' ' && i > 0 && (frame[i - 1] == ':' || frame[i - 1] == ',')) continue;
    out += c;
  }
  return out;
}

}  // namespace aslam
