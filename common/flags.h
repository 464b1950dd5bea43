#pragma once

// Command-line parsing for every aslam process (gflags). --help and -h print
// the usage and the process's own flags (those defined in *_main.cc files),
// not gflags' internals, and exit 0; a bad flag exits 1 with gflags' message.

namespace aslam {

void ParseFlags(int* argc, char*** argv, const char* usage);

}  // namespace aslam
