// aslam-rplidar: the Slamtec RPLIDAR (A1, A2, A3, S1, S2) driver. Publishes each revolution
// as LIDAR_SCAN; reconnects with backoff when the lidar is unplugged (drivers/rplidar/).

#include <gflags/gflags.h>

#include <cstdio>

#include "common/flags.h"
#include "drivers/rplidar/rplidar_lcm.h"

DEFINE_string(port, "", "serial port, e.g. /dev/rplidar or /dev/ttyUSB0 (default: rplidar.port)");
DEFINE_int32(baud, -1, "baud rate; 0 = the model's default (default: rplidar.baud)");
DEFINE_string(model, "", "a1, a2, a3, s1, s2 or auto (default: rplidar.model)");
DEFINE_string(scan_mode, "",
              "standard, express, auto, or a listed mode: boost, sensitivity, stability, "
              "denseboost (default: rplidar.scan_mode)");
DEFINE_string(config, "", "config file with an `rplidar:` section (default: built-in defaults)");
DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_int32(attempts, 0, "failed connection attempts in a row before exiting; 0 = never exit");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-rplidar [--port PATH] [--baud N] [--model a1|a2|a3|s1|s2|auto]\n"
                    "              [--scan_mode standard|express|auto|boost|...] [--config FILE] "
                    "[--lcm_url URL]");
  if (argc > 1) {
    std::fprintf(stderr, "aslam-rplidar: unexpected argument '%s' (see --help)\n", argv[1]);
    return 2;
  }
  aslam::RplidarProcessOptions options;
  options.config_file = FLAGS_config;
  options.lcm_url = FLAGS_lcm_url;
  options.port = FLAGS_port;
  options.baud = FLAGS_baud;
  options.model = FLAGS_model;
  options.scan_mode = FLAGS_scan_mode;
  options.attempts = FLAGS_attempts;
  return aslam::RunRplidarProcess(options);
}
