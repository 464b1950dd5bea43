// aslam-teleop: drive the robot by hand from a keyboard, publishing CMD_VEL, to check the
// base and its odometry before exploring. Hold a key to drive; let go and it stops.
// Key map and behaviour: tools/teleop.h; the process: tools/teleop_node.h.

#include <gflags/gflags.h>

#include "common/flags.h"
#include "tools/teleop_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "config file whose robot: section gives the speed limits");
DEFINE_double(rate, 10.0, "Hz at which CMD_VEL goes out while driving");
DEFINE_double(deadman_s, 0.6,
              "seconds without a motion key before the command returns to zero (above the "
              "keyboard's auto-repeat delay)");
DEFINE_bool(stdin, false, "read keys from stdin even when it is not a terminal (a pipe: tests)");

int main(int argc, char** argv) {
  aslam::ParseFlags(&argc, &argv,
                    "aslam-teleop [--lcm-url URL] [--config FILE] [--rate HZ] [--deadman-s S] "
                    "[--stdin]: drive the robot from the keyboard (CMD_VEL).");
  aslam::TeleopProcessOptions options;
  options.lcm_url = FLAGS_lcm_url;
  options.config_file = FLAGS_config;
  options.rate_hz = FLAGS_rate;
  options.deadman_s = FLAGS_deadman_s;
  options.keys_from_pipe = FLAGS_stdin;
  return aslam::RunTeleopProcess(options);
}
