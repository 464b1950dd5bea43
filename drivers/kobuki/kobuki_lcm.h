#pragma once

// aslam-kobuki on LCM: ODOMETRY per feedback packet, BASE_STATUS and DRIVER_STATUS, and
// CMD_VEL into the driver's safety layer.

#include <string>

#include "aslam/base_status_t.hpp"
#include "drivers/kobuki/kobuki_driver.h"

namespace aslam {

base_status_t ToLcm(const KobukiStatus& status);

// The process as its flags describe it; an empty string = the config's.
struct KobukiProcessOptions {
  std::string config_file;
  std::string lcm_url;
  std::string port;
  int attempts = 0;  // failed connection attempts in a row before exiting; 0 = retry forever
};

// Loads and checks the options, then drives the base until SIGINT/SIGTERM. Returns the exit
// code: 0 after a stop, 1 for a runtime failure (LCM, giving up), 2 for bad flags or config.
int RunKobukiProcess(const KobukiProcessOptions& options);

}  // namespace aslam
