#pragma once

// aslam-teleop as a process: keys from the terminal (raw mode, restored at every exit
// and on SIGINT, SIGTERM and SIGHUP) or from a pipe, through Teleop (tools/teleop.h), to
// CMD_VEL on LCM, stamped with the host's monotonic clock (drivers/io/host_clock.h).
// Commands go out at `rate_hz` while the robot is driven, at once when the command
// changes, and as zeros for a second after a stop; then nothing until the next key, so a
// forgotten aslam-teleop never fights aslam-nav. Quitting publishes a zero command.

#include <string>

namespace aslam {

struct TeleopProcessOptions {
  std::string lcm_url;      // "": ResolveLcmUrl's default
  std::string config_file;  // its robot: section gives the limits; "": the defaults
  double rate_hz = 10.0;
  double deadman_s = 0.6;
  bool keys_from_pipe = false;  // --stdin: read keys from a pipe (tests), not a terminal
};

// Runs until q, Ctrl-C, a signal or (from a pipe) the end of input. Returns 0; 2 for a
// bad flag value or a stdin that is not a terminal without keys_from_pipe; 1 when the
// config or LCM cannot be opened.
int RunTeleopProcess(const TeleopProcessOptions& options);

}  // namespace aslam
