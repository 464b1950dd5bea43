// write_map_log: an lcm log of COUNT SLAM_MAP messages of one map, PERIOD_MS apart, in the
// wire type SLAM publishes (zlib) or the legacy raw grid, for network tests
// (map_over_lossy_network_test.sh) that need real map sizes without running SLAM.
//   write_map_log MAP.yaml zlib|raw COUNT PERIOD_MS OUT.lcmlog

#include <cstdio>
#include <exception>
#include <string>

#include "common/channels.h"
#include "common/lcm_log_writer.h"
#include "common/map_io.h"
#include "common/types_lcm.h"

int main(int argc, char** argv) {
  using namespace aslam;
  if (argc != 6) {
    std::fprintf(stderr, "usage: write_map_log MAP.yaml zlib|raw COUNT PERIOD_MS OUT.lcmlog\n");
    return 2;
  }
  try {
    const std::string encoding = argv[2];
    const int count = std::stoi(argv[3]);
    const int64_t period_us = std::stoll(argv[4]) * 1000;
    if ((encoding != "zlib" && encoding != "raw") || count < 1 || period_us < 0) {
      std::fprintf(stderr, "write_map_log: bad arguments\n");
      return 2;
    }
    const OccupancyGrid grid = LoadMap(argv[1]).grid;
    LcmLogWriter log(argv[5]);
    for (int i = 0; i < count; ++i) {
      const int64_t utime = i * period_us;
      if (encoding == "zlib") {
        log.Write(channels::kSlamMap, utime, ToCompressedLcm(grid, utime, i + 1, kMapFrame));
      } else {
        log.Write(channels::kSlamMap, utime, ToLcm(grid, utime, i + 1, kMapFrame));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_map_log: %s\n", e.what());
    return 1;
  }
  return 0;
}
