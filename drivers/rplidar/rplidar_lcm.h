#pragma once

// aslam-rplidar on LCM: each revolution of the RPLIDAR published as LIDAR_SCAN.

#include <atomic>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "common/sensor_types.h"
#include "drivers/rplidar/rplidar_driver.h"

namespace aslam {

// Publishes a revolution on `channel` (LIDAR_SCAN), its sensor_pose the robot's lidar_mount.
void PublishLidarScan(lcm::LCM& lcm, const std::string& channel, const LidarScan& scan);

// The process as its flags describe it; an empty string or a negative number = the config's.
struct RplidarProcessOptions {
  std::string config_file;
  std::string lcm_url;
  std::string port;
  int baud = -1;  // -1 = the config's
  std::string model;
  std::string scan_mode;
  int attempts = 0;  // failed connection attempts in a row before exiting; 0 = retry forever
};

// Loads and checks the options, then publishes scans until SIGINT/SIGTERM. Returns the exit
// code: 0 after a stop, 1 for a runtime failure (LCM, giving up), 2 for bad flags or config.
int RunRplidarProcess(const RplidarProcessOptions& options);

}  // namespace aslam
