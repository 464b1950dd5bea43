#pragma once

// The sending side of EXPLORE_CONTROL (`aslam control`): publish one request and wait for
// the utility's EXPLORE_STATUS that answers it.

#include <optional>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "aslam/explore_status_t.hpp"
#include "utility/exploration_manager.h"

namespace aslam {

// Publishes `command` from `source` on `lcm`, then handles it until the first EXPLORE_STATUS
// arrives or `wait_s` (wall clock) passes. The utility answers every request at once, so
// the first status after the request is its answer; nullopt means none came (no utility
// on this bus).
std::optional<explore_status_t> SendExploreControl(lcm::LCM& lcm, ExploreCommand command,
                                                   const std::string& source, double wait_s);

// "paused: paused by request (2 reached, 0 failed)": a status as one line for a person.
std::string DescribeExploreStatus(const explore_status_t& status);

}  // namespace aslam
