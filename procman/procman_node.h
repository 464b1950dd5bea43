#pragma once

// Hosting of procman on LCM: the deputy loop (PROCMAN_ORDERS in, PROCMAN_STATUS
// out) and the sheriff's commands. Both print to stdout/stderr and return the
// process exit code.

#include <atomic>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "procman/deputy.h"
#include "procman/sheriff.h"

namespace aslam {

inline constexpr const char* kProcmanOrdersChannel = "PROCMAN_ORDERS";
inline constexpr const char* kProcmanStatusChannel = "PROCMAN_STATUS";

// Starts the deputy's processes, applies orders, publishes the status every
// status_period_s and on every change, until `stop` is set or the deputy shuts
// itself down (exit-when); then stops everything. Returns deputy.ExitCode().
int RunDeputyNode(lcm::LCM& lcm, Deputy& deputy, const std::atomic<bool>& stop,
                  double status_period_s = 1.0);

struct SheriffOptions {
  double wait_s = 6.0;  // for the first status, and for the orders to be carried out
};

// Prints the status table of every deputy heard; 1 if none is heard within wait_s.
int RunSheriffStatus(lcm::LCM& lcm, const SheriffOptions& options);
// Orders `command` for the process or group `target` (on every deputy that has it),
// repeating the whole desired state until the status shows it carried out; 1 if the
// target is unknown, no deputy is heard, or it is not carried out within wait_s.
int RunSheriffCommand(lcm::LCM& lcm, SheriffCommand command, const std::string& target,
                      const SheriffOptions& options);

}  // namespace aslam
