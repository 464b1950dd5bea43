#include "common/flags.h"

#include <cstdlib>
#include <cstring>

#include <gflags/gflags.h>

namespace aslam {

void ParseFlags(int* argc, char*** argv, const char* usage) {
  gflags::SetUsageMessage(usage);
  for (int i = 1; i < *argc; ++i) {
    const char* arg = (*argv)[i];
    if (std::strcmp(arg, "--help") == 0 || std::strcmp(arg, "-h") == 0) {
      gflags::ShowUsageWithFlagsRestrict((*argv)[0], "_main.cc");
      std::exit(0);
    }
  }
  gflags::ParseCommandLineFlags(argc, argv, true);
}

}  // namespace aslam
