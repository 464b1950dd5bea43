#pragma once

// Translators for the simulator's own messages.

#include <string>

#include "aslam/sim_status_t.hpp"
#include "drivers/sim/simulator.h"

namespace aslam {

struct SimStatusExtras {
  std::string world;
  uint64_t seed = 0;
  double real_time_factor = 0.0;
  int64_t commands_received = 0;
  int64_t messages_dropped = 0;
};

sim_status_t ToLcm(const SimStatus& status, const SimStatusExtras& extras);

}  // namespace aslam
