#include "drivers/sim/sim_config.h"

#include <cmath>
#include <stdexcept>

#include "drivers/sim/lidar_models.h"
#include "drivers/sim/simulator.h"

namespace aslam {

SimulatorOptions LoadSimulatorOptions(const ConfigReader& sim, const RobotOptions& robot) {
  SimulatorOptions options;
  options.robot = robot;
  sim.Read("seed", &options.seed);
  sim.ReadInRange("physics_rate_hz", &options.physics_rate_hz, 1.0, 10000.0);
  sim.ReadInRange("odometry_rate_hz", &options.odometry_rate_hz, 0.1, 10000.0);
  sim.ReadInRange("truth_rate_hz", &options.truth_rate_hz, 0.1, 10000.0);
  sim.ReadInRange("status_rate_hz", &options.status_rate_hz, 0.1, 100.0);
  sim.ReadInRange("command_timeout_s", &options.command_timeout_s, 0.01, 60.0);

  const ConfigReader lidar = sim.Section("lidar");
  // A model sets every lidar key; keys given beside it override the model's values.
  std::string model = options.lidar.model;
  lidar.Read("model", &model);
  try {
    options.lidar = LidarModelOptions(model);
  } catch (const std::invalid_argument& e) {
    lidar.Fail("model", e.what());
  }
  LidarOptions& l = options.lidar;
  lidar.ReadInRange("num_beams", &l.num_beams, 1, 100000);
  lidar.ReadInRange("rate_hz", &l.rate_hz, 0.1, 1000.0);
  lidar.ReadInRange("angle_min_rad", &l.angle_min_rad, -2.0 * M_PI, 2.0 * M_PI);
  lidar.ReadInRange("fov_rad", &l.fov_rad, 1e-3, 2.0 * M_PI);
  lidar.ReadInRange("range_min_m", &l.range_min_m, 0.0, 1000.0);
  lidar.ReadInRange("range_max_m", &l.range_max_m, 0.01, 1000.0);
  lidar.ReadInRange("noise_sigma_m", &l.noise_sigma_m, 0.0, 10.0);
  lidar.ReadInRange("noise_sigma_fraction", &l.noise_sigma_fraction, 0.0, 1.0);
  lidar.ReadInRange("dropout_probability", &l.dropout_probability, 0.0, 1.0);
  lidar.Read("swept", &l.swept);
  lidar.Read("clockwise", &l.clockwise);
  if (l.range_min_m >= l.range_max_m) lidar.Fail("range_min_m", "must be below range_max_m");

  const ConfigReader noise = sim.Section("odometry_noise");
  OdometryNoiseOptions& n = options.odometry_noise;
  noise.ReadInRange("alpha1", &n.alpha1, 0.0, 10.0);
  noise.ReadInRange("alpha2", &n.alpha2, 0.0, 10.0);
  noise.ReadInRange("alpha3", &n.alpha3, 0.0, 10.0);
  noise.ReadInRange("alpha4", &n.alpha4, 0.0, 10.0);

  sim.CheckAllKeysUsed();
  // Checks across keys (rates that must divide the physics rate) live with the simulator.
  try {
    ValidateSimulatorOptions(options);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(sim.file() + ": section sim: " + e.what());
  }
  return options;
}

SimulatorOptions LoadSimulatorOptionsFromFile(const std::string& file) {
  const RobotOptions robot = LoadRobotOptionsFromFile(file);
  return LoadSimulatorOptions(ConfigReader::FromOptionalFile(file, "sim"), robot);
}

}  // namespace aslam
