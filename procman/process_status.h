#pragma once

// procman's value types (no LCM): the actual state a deputy reports and the
// desired state a sheriff orders, both whole (docs/architecture.md §8).

#include <cstdint>
#include <string>
#include <vector>

namespace aslam {

// Start is synchronous (fork + exec confirmed through a close-on-exec pipe), so
// there is no separate "starting" state: a process is running once started.
enum class ProcessState {
  kStopped,  // not running and not wanted (never started, or stopped by order)
  kRunning,
  kStopping,  // TERM sent, KILL follows after stop_timeout_s
  kBackoff,   // ended, restart scheduled per policy
  kFailed,    // ended abnormally (or could not start); not restarted
  kExited,    // ended with code 0 on its own; not restarted
};

const char* ProcessStateName(ProcessState state);

struct ProcessStatus {
  std::string name;
  std::string group;
  std::string command_line;
  bool should_run = false;
  ProcessState state = ProcessState::kStopped;
  int pid = 0;        // 0 when not running
  int exit_code = 0;  // last exit: code, or -signal
  int restarts = 0;   // starts after the first
  int run_id = 0;
  double cpu_percent = 0.0;  // since the previous status
  int64_t rss_bytes = 0;
  double uptime_s = 0.0;
};

struct DeputyStatus {
  std::string deputy;
  int pid = 0;
  std::vector<ProcessStatus> processes;
};

struct ProcessOrder {
  std::string name;
  bool should_run = false;
  int run_id = 0;  // differs from the process's run_id: start a new run (restart)
};

struct DeputyOrders {
  std::string deputy;  // "" = any deputy
  std::vector<ProcessOrder> processes;
};

}  // namespace aslam
