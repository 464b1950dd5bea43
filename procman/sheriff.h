#pragma once

// The sheriff's logic (no LCM): from a deputy's whole actual state, the whole
// desired state after `start`, `stop` or `restart` of a name or group, whether
// the deputy has carried it out, and the status table.

#include <string>
#include <vector>

#include "procman/process_status.h"

namespace aslam {

enum class SheriffCommand { kStart, kStop, kRestart };

// Parses "start", "stop", "restart"; false otherwise.
bool ParseSheriffCommand(const std::string& text, SheriffCommand* command);

// The processes `target` names: the process of that name, else every process of that group.
std::vector<std::string> MatchTargets(const DeputyStatus& status, const std::string& target);

// Orders for every process of `status`: the targets changed per `command`, the others
// as they are. `start` of a process that is not running moves its run id (so one that
// exited runs again), `restart` always does, `stop` never does.
DeputyOrders ComputeOrders(const DeputyStatus& status, SheriffCommand command,
                           const std::vector<std::string>& targets);

// True once `status` shows every ordered process carried out: stopped, or running
// (or ended again) in the ordered run.
bool OrdersCarriedOut(const DeputyStatus& status, const DeputyOrders& orders);

// One row per process: name, group, state, pid, restarts, exit code, CPU %, RSS MB.
std::string FormatStatusTable(const std::vector<DeputyStatus>& deputies);

}  // namespace aslam
