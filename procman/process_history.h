#pragma once

// What happened to each supervised process over a run, from the deputy's successive whole
// statuses (live from PROCMAN_STATUS, or read back from a run's lcm log): how often it was
// restarted, how it last ended on its own, and whether it is gone for good. An end the
// deputy caused itself (a stop order, the shutdown) is not an end on its own. No LCM, no
// clock: callers decode and feed the statuses.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "procman/process_status.h"

namespace aslam {

struct ProcessHistory {
  std::string name;
  int restarts = 0;  // starts after the first (a sheriff's restart order counts too)
  // How it last ended on its own: an exit code, or the signal that killed it; neither if it
  // never did.
  std::optional<int> last_exit_code;
  std::optional<int> last_signal;
  ProcessState state = ProcessState::kStopped;  // in the latest status
  bool should_run = false;
};

class ProcessHistoryTracker {
 public:
  // One whole status. Processes are keyed by name (several deputies pool theirs), in the
  // order first heard. A status missed in between costs nothing but an end that a restart
  // already replaced: exit codes persist until the next end.
  void Add(const DeputyStatus& status);
  const std::vector<ProcessHistory>& processes() const { return processes_; }

 private:
  std::vector<ProcessHistory> processes_;
};

// A process that ended and will not be started again: failed (it crashed with restart
// `never`, or procman gave up restarting it) or exited with code 0 under `on-failure`;
// `expected_to_end` exiting is the run's normal end and does not count. One line saying which
// and how, or nullopt while every process runs or is coming back.
std::optional<std::string> LostProcess(const std::vector<ProcessHistory>& processes,
                                       const std::string& expected_to_end);

// "SIGKILL" for 9; "signal N" for a number without a name.
std::string SignalName(int signal);

// "SIGKILL", "exit 3" or "-" (never ended on its own).
std::string LastEnd(const ProcessHistory& process);

// "slam 1, nav 2": the processes restarted at least once and how often; "" if none was.
std::string RestartsSummary(const std::vector<ProcessHistory>& processes);

// {"restarts": 1, "last_exit_code": null, "last_signal": "SIGKILL"} as JSON fields.
std::vector<std::pair<std::string, std::string>> ProcessHistoryJsonFields(
    const ProcessHistory& process);

// {"slam": {"restarts": ...}, ...}: one JSON object, a line per process indented by `indent`.
std::string ProcessHistoriesJson(const std::vector<ProcessHistory>& processes,
                                 const std::string& indent);

}  // namespace aslam
