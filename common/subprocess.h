#pragma once

// One way to start a program as a child process (docs/architecture.md §8): procman's deputy,
// `aslam explore` in process mode and `aslam bench` all spawn through it. The start is
// synchronous: Spawn returns once exec has succeeded, or throws saying why it did not (the
// errno reaches the parent through a close-on-exec pipe). The child gets stdin from /dev/null,
// its stdout and stderr in a file (or this process's), default signal dispositions and an
// empty signal mask, and no file descriptor of this process but 0, 1 and 2.
//
// Reaping never blocks unless asked (Poll vs Wait); Terminate is TERM, then KILL after a
// grace period. A Subprocess destroyed while its child runs kills and reaps it: no orphan is
// left behind even on an error path.

#include <sys/types.h>

#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace aslam {

struct SubprocessOptions {
  // argv[0] is the program: a path, or a bare name looked up on PATH.
  std::vector<std::string> argv;
  // Added to this process's environment, replacing a variable of the same name.
  std::map<std::string, std::string> env;
  // stdout and stderr of the child; "" = this process's own.
  std::string output_path;
  bool append_output = false;  // append to output_path rather than truncate it
  // The child leads a process group of its own: Signal() reaches the whole group, whatever
  // the group still holds when the child ends is killed with it, and a terminal's Ctrl-C
  // reaches only this process, which can then stop the child in order.
  bool own_process_group = false;
  // PR_SET_PDEATHSIG: the child gets this signal when this process dies, even on a crash;
  // 0 = none (the child outlives this process).
  int parent_death_signal = 0;
};

// How a child ended: an exit code, or the signal that killed it.
struct ExitStatus {
  int code = 0;    // the exit code; 0 when killed by a signal
  int signal = 0;  // the signal that ended it; 0 when it exited

  static ExitStatus FromWaitStatus(int wait_status);
  bool exited() const { return signal == 0; }
  bool success() const { return signal == 0 && code == 0; }
  // The exit code, or minus the signal number.
  int CodeOrMinusSignal() const { return signal != 0 ? -signal : code; }
  // "exit code 3" or "killed by signal 9 (Killed)".
  std::string Describe() const;
};

// Spawn failed. exec_failed(): the child was created but the program could not be run
// (missing, not executable); what() is then "cannot run PROGRAM: REASON". Otherwise the
// output file could not be opened or no child could be created.
class SpawnError : public std::runtime_error {
 public:
  SpawnError(const std::string& what, int error_number, bool exec_failed)
      : std::runtime_error(what), error_number_(error_number), exec_failed_(exec_failed) {}
  int error_number() const { return error_number_; }
  bool exec_failed() const { return exec_failed_; }

 private:
  int error_number_;
  bool exec_failed_;
};

// A child reaped by ReapAnyChild.
struct ReapedChild {
  pid_t pid = 0;
  ExitStatus status;
};

class Subprocess {
 public:
  // No child.
  Subprocess() = default;
  // Starts the program; throws SpawnError.
  static Subprocess Spawn(const SubprocessOptions& options);

  // Kills (SIGKILL) and reaps a child still running.
  ~Subprocess();
  Subprocess(Subprocess&& other) noexcept;
  Subprocess& operator=(Subprocess&& other) noexcept;
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  // 0 if never started; kept after the child has been reaped.
  pid_t pid() const { return pid_; }
  // Started and not yet reaped.
  bool running() const { return pid_ > 0 && !reaped_; }
  // How it ended, once reaped (none if it was reaped by someone else, see Poll).
  const std::optional<ExitStatus>& exit_status() const { return exit_status_; }

  // Reaps the child if it has ended, without blocking. Returns how it ended (again on every
  // later call), or nothing while it runs. A child that is not this process's any more
  // (reaped elsewhere) is given up: nothing is returned and running() turns false.
  std::optional<ExitStatus> Poll();
  // Blocks until the child has ended and returns how.
  ExitStatus Wait();
  // Sends `signal` to the child (its group with own_process_group); false if it is not running.
  bool Signal(int signal);
  // TERM, then KILL if the child has not ended after grace_s (wall seconds); waits for it.
  // `while_waiting` runs between polls (e.g. to keep serving LCM), else this sleeps 10 ms.
  // An ended child is only reaped. killed_after_grace() then says whether KILL was needed.
  ExitStatus Terminate(double grace_s, const std::function<void()>& while_waiting = {});
  bool killed_after_grace() const { return killed_after_grace_; }
  // Records an end reaped with ReapAnyChild; true if `reaped` is this child.
  bool Claim(const ReapedChild& reaped);

 private:
  void OnReaped(const ExitStatus& status);
  void KillAndReap();

  pid_t pid_ = 0;
  bool own_process_group_ = false;
  bool reaped_ = false;
  bool killed_after_grace_ = false;
  std::optional<ExitStatus> exit_status_;
};

// A command run to its end: how it ended and what it wrote (stdout and stderr together).
struct CommandResult {
  ExitStatus status;
  std::string output;
};
// Runs `argv` (argv[0] a path or a name on PATH) and waits for it; throws SpawnError when it
// cannot be started.
CommandResult RunCommand(const std::vector<std::string>& argv);

// Reaps any one ended child of this process (waitpid(-1), never blocking). For a child
// subreaper (PR_SET_CHILD_SUBREAPER), which orphaned grandchildren come to: a Subprocess among
// the reaped must be told with Subprocess::Claim.
std::optional<ReapedChild> ReapAnyChild();

}  // namespace aslam
