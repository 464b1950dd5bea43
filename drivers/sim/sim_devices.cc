#include "drivers/sim/sim_devices.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "drivers/emulators/kobuki_emulator.h"
#include "drivers/emulators/rplidar_emulator.h"

namespace aslam {

SimDevices::SimDevices(const Simulator& simulator, const SimDevicesOptions& options)
    : simulator_(simulator), options_(options), rng_(simulator.options().seed * 7919 + 17) {
  std::error_code error;
  std::filesystem::create_directories(options_.dir, error);
  if (error) throw std::runtime_error("cannot create " + options_.dir + ": " + error.message());
  lidar_in_world_ = simulator_.true_pose().Compose(simulator_.options().robot.lidar_mount);

  KobukiEmulatorOptions base;
  base.link_path = options_.dir + "/kobuki";
  base.external_motion = true;  // the simulator moves the base, with its collisions
  wheel_base_m_ = base.wheel_base_m;
  kobuki_ = std::make_unique<KobukiEmulator>(base);

  RplidarEmulatorOptions lidar = RplidarEmulatorModel(options_.rplidar_model);
  lidar.link_path = options_.dir + "/rplidar";
  lidar.range_m = [this](double angle_cw_rad) { return RangeAt(angle_cw_rad); };
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

void SimDevices::AfterStep(const SimStepOutput& out) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    lidar_in_world_ = simulator_.true_pose().Compose(simulator_.options().robot.lidar_mount);
  }
  if (out.odometry) {
    const double v = out.odometry->linear_velocity_mps;
    const double w = out.odometry->angular_velocity_radps;
    kobuki_->SetWheelSpeeds(v - 0.5 * w * wheel_base_m_, v + 0.5 * w * wheel_base_m_);
  }
}

double SimDevices::RangeAt(double angle_cw_rad) {
  std::lock_guard<std::mutex> lock(mutex_);
  const LidarOptions& lidar = simulator_.options().lidar;
  const double range_m =
      simulator_.world().CastRay({lidar_in_world_.x_m, lidar_in_world_.y_m},
                                 lidar_in_world_.yaw_rad - angle_cw_rad, lidar.range_max_m);
  if (!std::isfinite(range_m)) return 0.0;  // no return
  std::normal_distribution<double> noise(0.0, options_.range_noise_sigma_m);
  return std::max(range_m + noise(rng_), 0.0);
}

}  // namespace aslam
