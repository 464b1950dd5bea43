#pragma once

// DRIVER_STATUS: a driver's DriverStatus on LCM.

#include <lcm/lcm-cpp.hpp>

#include "aslam/driver_status_t.hpp"
#include "drivers/io/driver_status.h"

namespace aslam {

driver_status_t ToLcm(const DriverStatus& status);
void PublishDriverStatus(lcm::LCM& lcm, const DriverStatus& status);

}  // namespace aslam
