#pragma once

// printf-style formatting into a std::string, for messages, details and tables; CSV fields,
// trimming, shell quoting and a small text file's whole content.

#include <string>
#include <vector>

namespace aslam {

// The whole formatted text, however long.
__attribute__((format(printf, 1, 2))) std::string Format(const char* format, ...);

// A CSV field, quoted when it holds a comma, a quote or a newline (RFC 4180).
std::string CsvField(const std::string& text);

// The text without leading and trailing spaces, tabs and line ends.
std::string Trim(const std::string& text);

// The word in single quotes for a POSIX shell ('it'\''s'): one argument whatever it holds.
std::string ShellQuoted(const std::string& word);
// The arguments as one shell command line, each quoted.
std::string ShellCommandLine(const std::vector<std::string>& argv);

// A file's whole content; "" when it cannot be read.
std::string ReadTextFile(const std::string& path);

}  // namespace aslam
