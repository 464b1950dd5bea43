#pragma once

// Translators between procman's value types and its lcmtypes.

#include <cstdint>
#include <string>

#include "aslam/procman_orders_t.hpp"
#include "aslam/procman_status_t.hpp"
#include "procman/process_status.h"

namespace aslam {

procman_status_t ToLcm(const DeputyStatus& status, int64_t utime);
// False (and `status` untouched) for a message whose counts do not match its arrays.
bool FromLcm(const procman_status_t& message, DeputyStatus* status);

procman_orders_t ToLcm(const DeputyOrders& orders, int64_t utime, const std::string& sheriff);
// False for a message whose counts do not match its arrays or that names no process.
bool FromLcm(const procman_orders_t& message, DeputyOrders* orders);

}  // namespace aslam
