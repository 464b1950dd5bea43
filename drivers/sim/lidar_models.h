#pragma once

// The simulator's lidar models, from their datasheets: rate, beams per sweep,
// field of view, range limits, range noise and the head's direction of turn.

#include <string>
#include <vector>

#include "drivers/sim/simulator_options.h"

namespace aslam {

// "ideal", "rplidar_a1", "rplidar_a2", "hokuyo_ust10", "hokuyo_urg04".
const std::vector<std::string>& LidarModelNames();

// The model's options; throws std::invalid_argument naming the model and the known ones.
LidarOptions LidarModelOptions(const std::string& model);

}  // namespace aslam
