#include "drivers/sim/sim_devices.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <stdexcept>

#include "drivers/emulators/kobuki_emulator.h"
#include "drivers/emulators/rplidar_emulator.h"

namespace aslam {

SimDevices::SimDevices(const Simulator& simulator, const SimDevicesOptions& options)
    : simulator_(simulator), options_(options), rng_(simulator.options().seed * 7919 + 17) {
  std::error_code error;
  std::filesystem::create_directories(options_.dir, error);
  if (error) throw std::runtime_error("cannot create " + options_.dir + ": " + error.message());
  lidar_in_world_.push_back(  // until the first step: the start, at any time
      {INT64_MIN, simulator_.true_pose().Compose(simulator_.options().robot.lidar_mount)});

  KobukiEmulatorOptions base;
  base.link_path = options_.dir + "/kobuki";
  base.external_motion = true;  // the simulator moves the base, with its collisions
  wheel_base_m_ = base.wheel_base_m;
  kobuki_ = std::make_unique<KobukiEmulator>(base);

  RplidarEmulatorOptions lidar = RplidarEmulatorModel(options_.rplidar_model);
  lidar.link_path = options_.dir + "/rplidar";
  lidar.range_m = [this](double angle_cw_rad, int64_t measured_utime) {
    return RangeAt(angle_cw_rad, measured_utime);
  };
  rplidar_ = std::make_unique<RplidarEmulator>(lidar);
}

SimDevices::~SimDevices() = default;

std::string SimDevices::kobuki_port() const { return kobuki_->link_path(); }
std::string SimDevices::rplidar_port() const { return rplidar_->link_path(); }

VelocityCommand SimDevices::Command(int64_t sim_utime) const {
  double left = 0.0, right = 0.0;
  kobuki_->CommandedWheelSpeeds(&left, &right);
  VelocityCommand command;
  command.utime = sim_utime;
  command.linear_mps = 0.5 * (left + right);
  command.angular_radps = (right - left) / wheel_base_m_;
  return command;
}

void SimDevices::AfterStep(const SimStepOutput& out, int64_t host_utime) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (lidar_in_world_.front().first == INT64_MIN) lidar_in_world_.clear();
    lidar_in_world_.push_back(
        {host_utime, simulator_.true_pose().Compose(simulator_.options().robot.lidar_mount)});
    // A second of steps: the lidar's thread asks for instants a few milliseconds back.
    while (lidar_in_world_.size() > 2 && lidar_in_world_.front().first < host_utime - 1000000) {
      lidar_in_world_.pop_front();
    }
  }
  if (out.odometry) {
    const double v = out.odometry->linear_velocity_mps;
    const double w = out.odometry->angular_velocity_radps;
    kobuki_->SetWheelSpeeds(v - 0.5 * w * wheel_base_m_, v + 0.5 * w * wheel_base_m_);
  }
}

Pose2d SimDevices::LidarInWorldAt(int64_t host_utime) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return LidarInWorldAtLocked(host_utime);
}

Pose2d SimDevices::LidarInWorldAtLocked(int64_t host_utime) const {
  const auto after = std::upper_bound(
      lidar_in_world_.begin(), lidar_in_world_.end(), host_utime,
      [](int64_t utime, const std::pair<int64_t, Pose2d>& step) { return utime < step.first; });
  if (after == lidar_in_world_.begin()) return after->second;
  if (after == lidar_in_world_.end()) return lidar_in_world_.back().second;
  const auto& [before_utime, before] = *std::prev(after);
  const double fraction = static_cast<double>(host_utime - before_utime) /
                          static_cast<double>(after->first - before_utime);
  return Interpolate(before, after->second, fraction);
}

double SimDevices::RangeAt(double angle_cw_rad, int64_t measured_utime) {
  std::lock_guard<std::mutex> lock(mutex_);
  const LidarOptions& lidar = simulator_.options().lidar;
  const Pose2d lidar_in_world = LidarInWorldAtLocked(measured_utime);
  const double range_m =
      simulator_.world().CastRay({lidar_in_world.x_m, lidar_in_world.y_m},
                                 lidar_in_world.yaw_rad - angle_cw_rad, lidar.range_max_m);
  if (!std::isfinite(range_m)) return 0.0;  // no return
  std::normal_distribution<double> noise(0.0, options_.range_noise_sigma_m);
  return std::max(range_m + noise(rng_), 0.0);
}

}  // namespace aslam
