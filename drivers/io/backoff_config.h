#pragma once

// The drivers' `reconnect_backoff_s: [INITIAL_S, MAX_S]` key: the first wait before reopening
// a device, doubled after each failed attempt up to the second.

#include "common/config.h"

namespace aslam {

// Leaves the values alone when the key is absent; a bad value is a ConfigError naming it.
void ReadReconnectBackoff(const ConfigReader& section, double* initial_s, double* max_s);

}  // namespace aslam
