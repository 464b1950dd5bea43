#pragma once

// printf-style formatting into a std::string, for messages, details and tables.

#include <string>

namespace aslam {

// The whole formatted text, however long.
__attribute__((format(printf, 1, 2))) std::string Format(const char* format, ...);

}  // namespace aslam
