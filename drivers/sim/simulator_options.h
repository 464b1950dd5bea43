#pragma once

// Options of the simulator library. Defaults are the shipped values; they are
// filled from YAML and validated by LoadSimulatorOptions (sim_config.h).

#include <cmath>
#include <cstdint>
#include <string>

#include "common/robot_config.h"

namespace aslam {

// The defaults are the "ideal" model: the paper's instantaneous 360° lidar.
// Named real models (drivers/sim/lidar_models.h) set every field below.
struct LidarOptions {
  std::string model = "ideal";
  int num_beams = 720;
  double rate_hz = 10.0;
  double angle_min_rad = -M_PI;  // first beam, sensor frame
  double fov_rad = 2.0 * M_PI;   // beams spread over [angle_min, angle_min + fov)
  double range_min_m = 0.15;
  double range_max_m = 12.0;
  double noise_sigma_m = 0.01;  // range noise sigma = noise_sigma_m + noise_sigma_fraction * range
  double noise_sigma_fraction = 0.005;
  double dropout_probability = 0.01;  // chance that a beam with a return reports none
  // A spinning head measures beam after beam over the period, each from the pose at its
  // own time (false: every beam at once, as an ideal sensor).
  bool swept = false;
  bool clockwise = false;  // the head's turn seen from above (beam order is always CCW)
};

// Probabilistic Robotics (Thrun et al.) odometry motion model, table 5.6:
// rot1, trans, rot2 each perturbed by zero-mean Gaussian noise with variance
//   rot:   alpha1*rot^2 + alpha2*trans^2
//   trans: alpha3*trans^2 + alpha4*(rot1^2 + rot2^2)
struct OdometryNoiseOptions {
  double alpha1 = 0.02;
  double alpha2 = 0.005;
  double alpha3 = 0.01;
  double alpha4 = 0.005;
};

struct SimulatorOptions {
  uint64_t seed = 1;
  double physics_rate_hz = 100.0;
  double odometry_rate_hz = 50.0;
  double truth_rate_hz = 50.0;
  double status_rate_hz = 1.0;
  double command_timeout_s = 0.5;  // older commands stop the robot
  LidarOptions lidar;
  // The simulated base's radius and limits and the lidar's mount are the robot's.
  RobotOptions robot;
  OdometryNoiseOptions odometry_noise;
};

}  // namespace aslam
