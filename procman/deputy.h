#pragma once

// The deputy: starts the processes of a launch config, supervises them and
// applies the sheriff's orders. No LCM here: the caller drives it by calling
// Step() often (it reaps without blocking), feeds it orders and publishes
// Status(); time comes from an injected Clock so tests can hold or advance it.
//
// Children start through common/subprocess.h: each is its own process group
// (signals go to the whole group) and gets PR_SET_PDEATHSIG(SIGKILL), so it dies
// with the deputy even on a crash; its stdout and stderr are appended to
// LOG_DIR/NAME.log.

#include <string>
#include <vector>

#include "common/subprocess.h"
#include "procman/launch_config.h"
#include "procman/process_status.h"

namespace aslam {

// Monotonic seconds.
class Clock {
 public:
  virtual ~Clock() = default;
  virtual double NowS() const = 0;
};

class SteadyClock : public Clock {
 public:
  double NowS() const override;
};

struct DeputyOptions {
  std::string log_dir;    // created if missing
  std::string exit_when;  // a process name: when it ends for good, shut everything down
  // Reap every child of this process (waitpid(-1)), not just the launched ones: for a
  // deputy that is a child subreaper (PR_SET_CHILD_SUBREAPER), so orphaned grandchildren
  // come to it and are reaped at once. Only where the host has no other children.
  bool reap_all_children = false;
};

class Deputy {
 public:
  // Throws std::invalid_argument for an exit_when naming no process, std::runtime_error
  // if the log folder cannot be created.
  Deputy(LaunchConfig config, DeputyOptions options, const Clock& clock);
  // Kills (SIGKILL) and reaps whatever still runs (each Subprocess does): no orphans even
  // on an error path.
  ~Deputy() = default;
  Deputy(const Deputy&) = delete;
  Deputy& operator=(const Deputy&) = delete;

  // Starts the auto_start processes, lowest start_order first.
  void Start();
  // Reaps ended children, restarts after backoff, escalates TERM to KILL after the
  // stop timeout. Returns true if any process changed state.
  bool Step();
  // Applies a whole desired state. Idempotent: the same orders again change nothing.
  // Orders for another deputy, and names not in the config, are ignored and counted.
  // Returns true if any process changed state.
  bool ApplyOrders(const DeputyOrders& orders);
  // Stops every child in reverse start order: TERM to the highest start_order tier, KILL
  // after the stop timeout, the next tier once that one has ended. Nothing restarts.
  void BeginShutdown();
  bool shutting_down() const { return shutting_down_; }
  // Shutting down and every child reaped.
  bool Finished() const;

  // The whole actual state; CPU % is measured since the previous call.
  DeputyStatus Status();

  // Abnormal ends so far: a non-zero exit, or a signal other than the TERM of a stop.
  int failures() const { return static_cast<int>(failure_reasons_.size()); }
  const std::vector<std::string>& failure_reasons() const { return failure_reasons_; }
  int ExitCode() const { return failures() > 0 ? 1 : 0; }
  int64_t ignored_orders() const { return ignored_orders_; }
  const LaunchConfig& config() const { return config_; }
  std::string LogPath(const std::string& name) const;

 private:
  struct Process {
    ProcessConfig config;
    std::string command_line;
    bool should_run = false;
    int run_id = 0;
    ProcessState state = ProcessState::kStopped;
    Subprocess child;  // running() while started and not yet reaped
    int exit_code = 0;
    int starts = 0;
    int consecutive_failures = 0;
    bool start_after_stop = false;  // a restart: start again once reaped
    bool kill_sent = false;
    double started_s = 0.0;
    double launch_at_s = -1.0;  // a delayed first start is pending
    double restart_at_s = 0.0;
    double kill_at_s = 0.0;
    // CPU accounting between Status() calls.
    pid_t sampled_pid = 0;
    long long sampled_ticks = 0;
    double sampled_s = 0.0;
    double cpu_percent = 0.0;
  };

  void Launch(Process& p);
  void Stop(Process& p);
  void OnExit(Process& p, const ExitStatus& status);
  void Fail(Process& p, const std::string& reason);
  void StopNextTier();
  std::vector<Process*> InStartOrder();

  LaunchConfig config_;
  DeputyOptions options_;
  const Clock& clock_;
  std::vector<Process> processes_;
  std::vector<std::string> failure_reasons_;
  int64_t ignored_orders_ = 0;
  bool shutting_down_ = false;
};

}  // namespace aslam
