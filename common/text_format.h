#pragma once

// printf-style formatting into a std::string, for messages, details and tables; CSV fields.

#include <string>

namespace aslam {

// The whole formatted text, however long.
__attribute__((format(printf, 1, 2))) std::string Format(const char* format, ...);

// A CSV field, quoted when it holds a comma, a quote or a newline (RFC 4180).
std::string CsvField(const std::string& text);

}  // namespace aslam
