#pragma once

// Loads the `sim:` section of a config file into SimulatorOptions,
// validated once at load time.

#include <string>

#include "common/config.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

// Reads and validates; throws ConfigError naming file, key and value.
SimulatorOptions LoadSimulatorOptions(const ConfigReader& sim_section);
// Convenience: the `sim` section of `file`; "" gives the defaults.
SimulatorOptions LoadSimulatorOptionsFromFile(const std::string& file);

}  // namespace aslam
