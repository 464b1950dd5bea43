#pragma once

// Loads the `sim:` section of a config file into SimulatorOptions,
// validated once at load time. The simulated base and lidar mount are the
// robot's (the `robot:` section, common/robot_config.h).

#include <string>

#include "common/config.h"
#include "common/robot_config.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

// Reads and validates; throws ConfigError naming file, key and value.
SimulatorOptions LoadSimulatorOptions(const ConfigReader& sim_section, const RobotOptions& robot);
// Convenience: the `robot` and `sim` sections of `file`; "" gives the defaults.
SimulatorOptions LoadSimulatorOptionsFromFile(const std::string& file);

}  // namespace aslam
