#include "common/subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <utility>

#include "common/text_format.h"

extern char** environ;

namespace aslam {
namespace {

// waitpid, retried on EINTR.
pid_t WaitPid(pid_t pid, int* wait_status, int flags) {
  pid_t reaped;
  do {
    reaped = waitpid(pid, wait_status, flags);
  } while (reaped < 0 && errno == EINTR);
  return reaped;
}

// In the child, between fork and exec: only async-signal-safe calls from here on.
void UseAs(int fd, int target) {
  if (fd == target) {
    fcntl(fd, F_SETFD, 0);  // keep it across exec
  } else {
    dup2(fd, target);
  }
}

void CloseFrom(unsigned int first, unsigned int last, int max_fd) {
  if (first > last) return;
  if (close_range(first, last, 0) == 0) return;
  for (int fd = static_cast<int>(first); fd <= max_fd && fd <= static_cast<int>(last); ++fd) {
    close(fd);
  }
}

[[noreturn]] void ExecChild(const SubprocessOptions& options, pid_t parent, char** argv,
                            char** envp, int null_fd, int output_fd, int exec_error_fd,
                            int max_fd) {
  if (options.own_process_group) setpgid(0, 0);
  if (options.parent_death_signal != 0) {
    prctl(PR_SET_PDEATHSIG, options.parent_death_signal);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
  }
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  for (const int sig : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD}) signal(sig, SIG_DFL);
  UseAs(null_fd, STDIN_FILENO);
  if (output_fd >= 0) {
    UseAs(output_fd, STDOUT_FILENO);
    UseAs(output_fd, STDERR_FILENO);
  }
  // Nothing of the parent's (LCM sockets, files) leaks into the child; the error pipe closes on
  // exec.
  CloseFrom(3, static_cast<unsigned int>(exec_error_fd) - 1, max_fd);
  CloseFrom(static_cast<unsigned int>(exec_error_fd) + 1, UINT_MAX, max_fd);
  execvpe(argv[0], argv, envp);
  const int exec_errno = errno;
  (void)!write(exec_error_fd, &exec_errno, sizeof exec_errno);
  _exit(127);
}

}  // namespace

ExitStatus ExitStatus::FromWaitStatus(int wait_status) {
  ExitStatus status;
  if (WIFEXITED(wait_status)) status.code = WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) status.signal = WTERMSIG(wait_status);
  return status;
}

std::string ExitStatus::Describe() const {
  if (signal == 0) return "exit code " + std::to_string(code);
  return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
}

Subprocess Subprocess::Spawn(const SubprocessOptions& options) {
  if (options.argv.empty() || options.argv[0].empty()) {
    throw SpawnError("cannot run a program without a name", EINVAL, false);
  }
  // Everything the child needs is built here: between fork and exec only async-signal-safe
  // calls are allowed.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry(*e);
    if (!options.env.count(entry.substr(0, entry.find('=')))) env_strings.push_back(entry);
  }
  for (const auto& [key, value] : options.env) env_strings.push_back(key + "=" + value);
  std::vector<char*> envp;
  for (std::string& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> arg_strings = options.argv;
  std::vector<char*> argv;
  for (std::string& s : arg_strings) argv.push_back(s.data());
  argv.push_back(nullptr);
  const long open_max = sysconf(_SC_OPEN_MAX);
  const int max_fd = open_max > 0 && open_max < 65536 ? static_cast<int>(open_max) - 1 : 65535;

  int output_fd = -1;
  if (!options.output_path.empty()) {
    const int mode = options.append_output ? O_APPEND : O_TRUNC;
    output_fd = open(options.output_path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | mode, 0644);
    if (output_fd < 0) {
      const int error = errno;
      throw SpawnError("cannot write " + options.output_path + ": " + std::strerror(error), error,
                       false);
    }
  }
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  int exec_pipe[2] = {-1, -1};
  if (null_fd < 0 || pipe2(exec_pipe, O_CLOEXEC) != 0) {
    const int error = errno;
    for (const int fd : {output_fd, null_fd}) {
      if (fd >= 0) close(fd);
    }
    throw SpawnError(std::string("cannot start: ") + std::strerror(error), error, false);
  }

  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    ExecChild(options, parent, argv.data(), envp.data(), null_fd, output_fd, exec_pipe[1], max_fd);
  }
  const int fork_errno = errno;
  for (const int fd : {output_fd, null_fd, exec_pipe[1]}) {
    if (fd >= 0) close(fd);
  }
  if (pid < 0) {
    close(exec_pipe[0]);
    throw SpawnError(std::string("fork failed: ") + std::strerror(fork_errno), fork_errno, false);
  }
  // Also here, so no signal to the group can race the child's own setpgid.
  if (options.own_process_group) setpgid(pid, pid);
  int exec_errno = 0;
  ssize_t n;
  do {
    n = read(exec_pipe[0], &exec_errno, sizeof exec_errno);
  } while (n < 0 && errno == EINTR);
  close(exec_pipe[0]);
  if (n == static_cast<ssize_t>(sizeof exec_errno)) {
    // Pipe data means exec failed; the child has exited already.
    int wait_status = 0;
    WaitPid(pid, &wait_status, 0);
    throw SpawnError("cannot run " + options.argv[0] + ": " + std::strerror(exec_errno), exec_errno,
                     true);
  }
  Subprocess child;
  child.pid_ = pid;
  child.own_process_group_ = options.own_process_group;
  return child;
}

Subprocess::~Subprocess() { KillAndReap(); }

Subprocess::Subprocess(Subprocess&& other) noexcept
    : pid_(std::exchange(other.pid_, 0)),
      own_process_group_(other.own_process_group_),
      reaped_(other.reaped_),
      killed_after_grace_(other.killed_after_grace_),
      exit_status_(std::move(other.exit_status_)) {}

Subprocess& Subprocess::operator=(Subprocess&& other) noexcept {
  if (this != &other) {
    KillAndReap();
    pid_ = std::exchange(other.pid_, 0);
    own_process_group_ = other.own_process_group_;
    reaped_ = other.reaped_;
    killed_after_grace_ = other.killed_after_grace_;
    exit_status_ = std::move(other.exit_status_);
  }
  return *this;
}

void Subprocess::KillAndReap() {
  if (!running()) return;
  if (own_process_group_) kill(-pid_, SIGKILL);
  kill(pid_, SIGKILL);
  int wait_status = 0;
  WaitPid(pid_, &wait_status, 0);
  reaped_ = true;
}

void Subprocess::OnReaped(const ExitStatus& status) {
  reaped_ = true;
  exit_status_ = status;
  if (own_process_group_) kill(-pid_, SIGKILL);  // whatever it left in its group goes with it
}

std::optional<ExitStatus> Subprocess::Poll() {
  if (!running()) return exit_status_;
  int wait_status = 0;
  const pid_t reaped = WaitPid(pid_, &wait_status, WNOHANG);
  if (reaped == pid_) {
    OnReaped(ExitStatus::FromWaitStatus(wait_status));
  } else if (reaped < 0 && errno == ECHILD) {
    reaped_ = true;  // not this process's child any more: someone else reaped it
  }
  return exit_status_;
}

ExitStatus Subprocess::Wait() {
  if (running()) {
    int wait_status = 0;
    if (WaitPid(pid_, &wait_status, 0) == pid_) {
      OnReaped(ExitStatus::FromWaitStatus(wait_status));
    } else {
      reaped_ = true;
    }
  }
  if (!exit_status_) throw std::logic_error("Subprocess: no child to wait for");
  return *exit_status_;
}

bool Subprocess::Signal(int signal) {
  if (!running()) return false;
  return kill(own_process_group_ ? -pid_ : pid_, signal) == 0;
}

ExitStatus Subprocess::Terminate(double grace_s, const std::function<void()>& while_waiting) {
  using Clock = std::chrono::steady_clock;
  if (Poll() || !running()) return Wait();
  Signal(SIGTERM);
  const Clock::time_point term = Clock::now();
  while (!Poll() && running()) {
    if (std::chrono::duration<double>(Clock::now() - term).count() > grace_s) {
      Signal(SIGKILL);
      killed_after_grace_ = true;
      break;
    }
    if (while_waiting) {
      while_waiting();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  return Wait();
}

bool Subprocess::Claim(const ReapedChild& reaped) {
  if (!running() || reaped.pid != pid_) return false;
  OnReaped(reaped.status);
  return true;
}

CommandResult RunCommand(const std::vector<std::string>& argv) {
  const char* tmpdir = std::getenv("TMPDIR");
  std::string path = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/aslam-command.XXXXXX";
  const int fd = mkstemp(path.data());
  if (fd < 0) throw SpawnError("cannot make a file for the output of " + argv.at(0), errno, false);
  close(fd);
  CommandResult result;
  try {
    SubprocessOptions options;
    options.argv = argv;
    options.output_path = path;
    result.status = Subprocess::Spawn(options).Wait();
  } catch (...) {
    unlink(path.c_str());
    throw;
  }
  result.output = ReadTextFile(path);
  unlink(path.c_str());
  return result;
}

std::optional<ReapedChild> ReapAnyChild() {
  int wait_status = 0;
  const pid_t pid = WaitPid(-1, &wait_status, WNOHANG);
  if (pid <= 0) return std::nullopt;
  return ReapedChild{pid, ExitStatus::FromWaitStatus(wait_status)};
}

}  // namespace aslam
