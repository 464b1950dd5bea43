#pragma once

// Devices in the loop: the simulated base speaks the Kobuki protocol and the simulated lidar
// the RPLIDAR protocol, each on a pseudo-terminal behind a link in one folder, so the real
// driver processes (aslam-kobuki, aslam-rplidar) stand between the simulator and the stack
// exactly as on a robot. The emulators are the drivers' test devices (drivers/emulators/).

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <utility>

#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "drivers/sim/simulator.h"

namespace aslam {

class KobukiEmulator;
class RplidarEmulator;

struct SimDevicesOptions {
  std::string dir;                   // DIR/kobuki and DIR/rplidar are the ports (created)
  std::string rplidar_model = "a2";  // a1, a2, a3, s1, s2: rate and sample times
  double range_noise_sigma_m = 0.01;
};

class SimDevices {
 public:
  // The world, the lidar's mount and range come from `simulator`, which must outlive this.
  // Throws std::runtime_error if the folder or a pseudo-terminal cannot be made.
  SimDevices(const Simulator& simulator, const SimDevicesOptions& options);
  ~SimDevices();
  SimDevices(const SimDevices&) = delete;
  SimDevices& operator=(const SimDevices&) = delete;

  // What the base's driver last told it, as a command for the simulated base.
  VelocityCommand Command(int64_t sim_utime) const;
  // After each physics step, which brings the simulation to `host_utime` on the host's
  // clock: the emulated wheels turn as the simulator's (noisy) odometry measured over the
  // step, and the lidar looks from the true pose along it.
  void AfterStep(const SimStepOutput& out, int64_t host_utime);

  std::string kobuki_port() const;
  std::string rplidar_port() const;

  // The lidar's true pose at a host time, interpolated between the steps around it (held
  // at the ends: before the first step, or when the simulation runs late).
  Pose2d LidarInWorldAt(int64_t host_utime) const;

 private:
  // The lidar's range at an angle clockwise from its front (the RPLIDAR's convention), from
  // the true pose at `measured_utime` (host clock): called by the lidar emulator's thread,
  // beam by beam, so scans sweep as the robot moves.
  double RangeAt(double angle_cw_rad, int64_t measured_utime);
  Pose2d LidarInWorldAtLocked(int64_t host_utime) const;

  const Simulator& simulator_;
  SimDevicesOptions options_;
  double wheel_base_m_ = 0.230;
  mutable std::mutex mutex_;
  // The lidar's true pose after each recent step, by host time (oldest first).
  std::deque<std::pair<int64_t, Pose2d>> lidar_in_world_;
  std::mt19937_64 rng_;
  std::unique_ptr<KobukiEmulator> kobuki_;
  std::unique_ptr<RplidarEmulator> rplidar_;
};

}  // namespace aslam
