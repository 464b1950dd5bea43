// aslam-kobuki: the Yujin Kobuki base driver. Publishes ODOMETRY (50 Hz), BASE_STATUS and
// DRIVER_STATUS; drives the base from CMD_VEL within the safety limits (drivers/kobuki/).

#include <gflags/gflags.h>

#include <cstdio>

#include "common/flags.h"
#include "drivers/kobuki/kobuki_lcm.h"

DEFINE_string(port, "", "serial port, e.g. /dev/kobuki or /dev/ttyUSB0 (default: kobuki.port)");
DEFINE_string(config, "",
              "config file with `kobuki:` and `robot:` sections (default: built-in defaults)");
DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_int32(attempts, 0, "failed connection attempts in a row before exiting; 0 = never exit");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-kobuki [--port PATH] [--config FILE] [--lcm_url URL] [--attempts N]");
  if (argc > 1) {
    std::fprintf(stderr, "aslam-kobuki: unexpected argument '%s' (see --help)\n", argv[1]);
    return 2;
  }
  aslam::KobukiProcessOptions options;
  options.config_file = FLAGS_config;
  options.lcm_url = FLAGS_lcm_url;
  options.port = FLAGS_port;
  options.attempts = FLAGS_attempts;
  return aslam::RunKobukiProcess(options);
}
