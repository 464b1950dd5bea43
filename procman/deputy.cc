#include "procman/deputy.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace aslam {
namespace {

std::string Quote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_of(" \t\"'\\$") == std::string::npos) return arg;
  std::string quoted = "'";
  for (char c : arg) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string CommandLine(const ProcessConfig& config) {
  std::string line = Quote(config.command);
  for (const auto& arg : config.args) line += " " + Quote(arg);
  return line;
}

std::string DescribeExit(int wait_status) {
  if (WIFEXITED(wait_status)) return "exit code " + std::to_string(WEXITSTATUS(wait_status));
  if (WIFSIGNALED(wait_status)) {
    const int sig = WTERMSIG(wait_status);
    return "killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  return "ended";
}

// utime + stime of `pid` in clock ticks (fields 14 and 15 of /proc/PID/stat); -1 if gone.
long long CpuTicks(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The command name (field 2) may hold spaces and parentheses: parse after the last ')'.
  const std::size_t close = text.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream fields(text.substr(close + 1));
  std::string field;
  long long utime = 0, stime = 0;
  for (int index = 3; index <= 15 && fields >> field; ++index) {
    if (index == 14) utime = std::atoll(field.c_str());
    if (index == 15) stime = std::atoll(field.c_str());
  }
  return fields ? utime + stime : -1;
}

// Resident set size from /proc/PID/statm (second field, in pages); 0 if gone.
int64_t RssBytes(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/statm");
  long long size_pages = 0, resident_pages = 0;
  if (!(in >> size_pages >> resident_pages)) return 0;
  return static_cast<int64_t>(resident_pages) * sysconf(_SC_PAGESIZE);
}

void WriteAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // a log line is not worth failing a start for
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

double SteadyClock::NowS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

const char* ProcessStateName(ProcessState state) {
  switch (state) {
    case ProcessState::kStopped:
      return "stopped";
    case ProcessState::kRunning:
      return "running";
    case ProcessState::kStopping:
      return "stopping";
    case ProcessState::kBackoff:
      return "backoff";
    case ProcessState::kFailed:
      return "failed";
    case ProcessState::kExited:
      return "exited";
  }
  return "?";
}

Deputy::Deputy(LaunchConfig config, DeputyOptions options, const Clock& clock)
    : config_(std::move(config)), options_(std::move(options)), clock_(clock) {
  if (options_.log_dir.empty()) options_.log_dir = ".";
  std::error_code error;
  std::filesystem::create_directories(options_.log_dir, error);
  if (error) {
    throw std::runtime_error("cannot create log folder " + options_.log_dir + ": " +
                             error.message());
  }
  bool exit_when_found = options_.exit_when.empty();
  for (const auto& pc : config_.processes) {
    Process p;
    p.config = pc;
    p.command_line = CommandLine(pc);
    p.should_run = pc.auto_start;
    processes_.push_back(std::move(p));
    exit_when_found |= pc.name == options_.exit_when;
  }
  if (!exit_when_found) {
    throw std::invalid_argument("exit-when names no process of the launch config: " +
                                options_.exit_when);
  }
}

Deputy::~Deputy() {
  for (auto& p : processes_) {
    if (p.pid <= 0) continue;
    kill(-p.pid, SIGKILL);
    kill(p.pid, SIGKILL);
    int status = 0;
    while (waitpid(p.pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

std::string Deputy::LogPath(const std::string& name) const {
  return options_.log_dir + "/" + name + ".log";
}

std::vector<Deputy::Process*> Deputy::InStartOrder() {
  std::vector<Process*> order;
  for (auto& p : processes_) order.push_back(&p);
  std::stable_sort(order.begin(), order.end(), [](const Process* a, const Process* b) {
    return a->config.start_order < b->config.start_order;
  });
  return order;
}

void Deputy::Start() {
  const double now_s = clock_.NowS();
  for (Process* p : InStartOrder()) {
    if (!p->should_run || p->pid != 0 || p->state == ProcessState::kStopping) continue;
    if (p->config.start_delay_s > 0.0) {
      p->launch_at_s = now_s + p->config.start_delay_s;
    } else {
      Launch(*p);
    }
  }
}

void Deputy::Fail(Process& p, const std::string& reason) {
  failure_reasons_.push_back(p.config.name + ": " + reason);
}

void Deputy::Launch(Process& p) {
  const double now_s = clock_.NowS();
  const int log_fd =
      open(LogPath(p.config.name).c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  int exec_pipe[2] = {-1, -1};
  if (log_fd < 0 || null_fd < 0 || pipe2(exec_pipe, O_CLOEXEC) != 0) {
    const std::string reason = std::string("cannot start: ") + std::strerror(errno);
    for (int fd : {log_fd, null_fd}) {
      if (fd >= 0) close(fd);
    }
    p.state = ProcessState::kFailed;
    p.exit_code = 127;
    Fail(p, reason);
    return;
  }
  WriteAll(log_fd, "--- aslam-procman: start " + std::to_string(p.starts + 1) + " (run " +
                       std::to_string(p.run_id) + "): " + p.command_line + "\n");

  // Everything the child needs is built here: between fork and exec only
  // async-signal-safe calls are allowed.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry(*e);
    const std::string key = entry.substr(0, entry.find('='));
    if (!p.config.env.count(key)) env_strings.push_back(entry);
  }
  for (const auto& [key, value] : p.config.env) env_strings.push_back(key + "=" + value);
  std::vector<char*> envp;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> arg_strings = {p.config.command};
  arg_strings.insert(arg_strings.end(), p.config.args.begin(), p.config.args.end());
  std::vector<char*> argv;
  for (auto& s : arg_strings) argv.push_back(s.data());
  argv.push_back(nullptr);

  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);                        // its own group: signals reach its children too
    prctl(PR_SET_PDEATHSIG, SIGKILL);     // dies with the deputy, even if the deputy crashes
    if (getppid() != parent) _exit(126);  // the deputy died before prctl took effect
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    for (int sig : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD}) signal(sig, SIG_DFL);
    dup2(null_fd, STDIN_FILENO);
    dup2(log_fd, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    execvpe(argv[0], argv.data(), envp.data());
    const int exec_errno = errno;
    (void)!write(exec_pipe[1], &exec_errno, sizeof exec_errno);
    _exit(127);
  }
  close(exec_pipe[1]);
  close(null_fd);
  if (pid < 0) {
    const std::string reason = std::string("fork failed: ") + std::strerror(errno);
    WriteAll(log_fd, "--- aslam-procman: " + reason + "\n");
    close(log_fd);
    close(exec_pipe[0]);
    p.state = ProcessState::kFailed;
    p.exit_code = 127;
    Fail(p, reason);
    return;
  }
  setpgid(pid, pid);  // also here, so no signal to the group can race the child's own call
  int exec_errno = 0;
  ssize_t n;
  do {
    n = read(exec_pipe[0], &exec_errno, sizeof exec_errno);
  } while (n < 0 && errno == EINTR);
  close(exec_pipe[0]);
  ++p.starts;
  p.launch_at_s = -1.0;
  p.kill_sent = false;
  p.start_after_stop = false;
  if (n == static_cast<ssize_t>(sizeof exec_errno)) {
    // Pipe data means exec failed; the child has exited already.
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    const std::string reason = "cannot run " + p.config.command + ": " + std::strerror(exec_errno);
    WriteAll(log_fd, "--- aslam-procman: " + reason + "\n");
    close(log_fd);
    p.pid = 0;
    p.state = ProcessState::kFailed;  // a missing program does not appear by retrying
    p.exit_code = 127;
    Fail(p, reason);
    return;
  }
  close(log_fd);
  p.pid = pid;
  p.state = ProcessState::kRunning;
  p.started_s = now_s;
}

void Deputy::Stop(Process& p) {
  if (p.pid <= 0) return;
  if (p.state != ProcessState::kStopping) {
    kill(-p.pid, SIGTERM);
    p.state = ProcessState::kStopping;
    p.kill_at_s = clock_.NowS() + config_.stop_timeout_s;
    p.kill_sent = false;
  }
}

void Deputy::OnExit(Process& p, int wait_status) {
  const pid_t pid = p.pid;
  p.pid = 0;
  kill(-pid, SIGKILL);  // whatever it left in its group goes with it
  const bool stopping = p.state == ProcessState::kStopping;
  p.exit_code = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status)
                                       : (WIFSIGNALED(wait_status) ? -WTERMSIG(wait_status) : 0);
  const bool our_term =
      stopping && !p.kill_sent && WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGTERM;
  const bool abnormal = p.exit_code != 0 && !our_term;
  const double now_s = clock_.NowS();
  if (abnormal)
    Fail(p, DescribeExit(wait_status) + (stopping && p.kill_sent ? " after the stop timeout" : ""));
  {
    const int log_fd = open(LogPath(p.config.name).c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (log_fd >= 0) {
      WriteAll(log_fd, "--- aslam-procman: " + DescribeExit(wait_status) + "\n");
      close(log_fd);
    }
  }
  if (stopping) {
    p.state = ProcessState::kStopped;
    if (p.start_after_stop && p.should_run && !shutting_down_) Launch(p);
    return;
  }
  if (now_s - p.started_s >= p.config.backoff.reset_after_s) p.consecutive_failures = 0;
  const RestartPolicy policy = p.config.restart;
  const bool restart =
      p.should_run && !shutting_down_ &&
      (policy == RestartPolicy::kAlways || (policy == RestartPolicy::kOnFailure && abnormal));
  if (restart) {
    ++p.consecutive_failures;
    p.restart_at_s = now_s + BackoffDelayS(p.config.backoff, p.consecutive_failures);
    p.state = ProcessState::kBackoff;
  } else {
    p.state = abnormal ? ProcessState::kFailed : ProcessState::kExited;
  }
}

bool Deputy::Step() {
  bool changed = false;
  if (options_.reap_all_children) {
    int status = 0;
    pid_t reaped;
    while ((reaped = waitpid(-1, &status, WNOHANG)) > 0) {
      for (auto& p : processes_) {
        if (p.pid == reaped) {
          OnExit(p, status);
          changed = true;
          break;
        }
      }  // anything else was an orphaned grandchild: reaped, nothing more to do
    }
  }
  for (auto& p : processes_) {
    if (p.pid <= 0) continue;
    int status = 0;
    const pid_t reaped = waitpid(p.pid, &status, WNOHANG);
    if (reaped == p.pid) {
      OnExit(p, status);
      changed = true;
    } else if (reaped < 0 && errno == ECHILD) {
      // Not our child any more (cannot happen unless someone reaped it): forget it.
      p.pid = 0;
      p.state = ProcessState::kStopped;
      changed = true;
    }
  }
  const double now_s = clock_.NowS();
  for (auto& p : processes_) {
    if (p.state == ProcessState::kStopping && !p.kill_sent && now_s >= p.kill_at_s) {
      kill(-p.pid, SIGKILL);
      p.kill_sent = true;
    }
    if (p.launch_at_s >= 0.0 && now_s >= p.launch_at_s && p.should_run && !shutting_down_ &&
        p.pid == 0) {
      Launch(p);
      changed = true;
    }
    if (p.state == ProcessState::kBackoff && !shutting_down_ && now_s >= p.restart_at_s) {
      Launch(p);
      changed = true;
    }
  }
  if (shutting_down_) StopNextTier();
  if (!options_.exit_when.empty() && !shutting_down_) {
    for (const auto& p : processes_) {
      if (p.config.name == options_.exit_when &&
          (p.state == ProcessState::kExited || p.state == ProcessState::kFailed)) {
        BeginShutdown();
        changed = true;
        break;
      }
    }
  }
  return changed;
}

bool Deputy::ApplyOrders(const DeputyOrders& orders) {
  if (shutting_down_ || (!orders.deputy.empty() && orders.deputy != config_.deputy)) {
    ++ignored_orders_;
    return false;
  }
  bool changed = false;
  for (const auto& order : orders.processes) {
    auto found = std::find_if(processes_.begin(), processes_.end(),
                              [&](const Process& p) { return p.config.name == order.name; });
    if (found == processes_.end()) {
      ++ignored_orders_;
      continue;
    }
    Process& p = *found;
    const ProcessState before = p.state;
    if (!order.should_run) {
      p.should_run = false;
      p.start_after_stop = false;
      p.launch_at_s = -1.0;
      p.run_id = order.run_id;
      if (p.state == ProcessState::kRunning) Stop(p);
      if (p.state == ProcessState::kBackoff) p.state = ProcessState::kStopped;
    } else {
      // A new run is wanted when the run id moved or the process was not wanted before;
      // otherwise (a repeated order) an exited or failed process stays so.
      const bool new_run = order.run_id != p.run_id || !p.should_run;
      const bool bumped = order.run_id != p.run_id;
      p.should_run = true;
      p.run_id = order.run_id;
      if (new_run) {
        if (p.state == ProcessState::kRunning) {
          if (bumped) {
            Stop(p);
            p.start_after_stop = true;
          }
        } else if (p.state == ProcessState::kStopping) {
          p.start_after_stop = true;
        } else {
          p.consecutive_failures = 0;
          Launch(p);
        }
      }
    }
    changed |= p.state != before;
  }
  return changed;
}

void Deputy::BeginShutdown() {
  if (shutting_down_) return;
  shutting_down_ = true;
  for (auto& p : processes_) {
    p.should_run = false;
    p.start_after_stop = false;
    p.launch_at_s = -1.0;
    if (p.state == ProcessState::kBackoff) p.state = ProcessState::kStopped;
  }
  StopNextTier();
}

void Deputy::StopNextTier() {
  // One start_order tier at a time, highest first, each once the one above has ended:
  // e.g. a logger started first records the others' last messages.
  int tier = 0;
  bool any = false;
  for (const auto& p : processes_) {
    if (p.state == ProcessState::kStopping) return;
    if (p.state == ProcessState::kRunning && (!any || p.config.start_order > tier)) {
      tier = p.config.start_order;
      any = true;
    }
  }
  std::vector<Process*> order = InStartOrder();
  std::reverse(order.begin(), order.end());
  for (Process* p : order) {
    if (p->state == ProcessState::kRunning && p->config.start_order == tier) Stop(*p);
  }
}

bool Deputy::Finished() const {
  return shutting_down_ && std::all_of(processes_.begin(), processes_.end(),
                                       [](const Process& p) { return p.pid <= 0; });
}

DeputyStatus Deputy::Status() {
  static const double ticks_per_s = static_cast<double>(sysconf(_SC_CLK_TCK));
  const double now_s = clock_.NowS();
  DeputyStatus status;
  status.deputy = config_.deputy;
  status.pid = static_cast<int>(getpid());
  for (auto& p : processes_) {
    ProcessStatus s;
    s.name = p.config.name;
    s.group = p.config.group;
    s.command_line = p.command_line;
    s.should_run = p.should_run;
    s.state = p.state;
    s.pid = static_cast<int>(p.pid);
    s.exit_code = p.exit_code;
    s.restarts = std::max(0, p.starts - 1);
    s.run_id = p.run_id;
    if (p.pid > 0) {
      s.uptime_s = now_s - p.started_s;
      s.rss_bytes = RssBytes(p.pid);
      const long long ticks = CpuTicks(p.pid);
      if (p.sampled_pid != p.pid || ticks < 0) {
        p.cpu_percent = 0.0;
        p.sampled_pid = p.pid;
        p.sampled_ticks = std::max(0LL, ticks);
        p.sampled_s = now_s;
      } else if (now_s - p.sampled_s >= 0.1) {  // shorter windows say nothing at 100 ticks/s
        p.cpu_percent = 100.0 * (ticks - p.sampled_ticks) / ticks_per_s / (now_s - p.sampled_s);
        p.sampled_ticks = ticks;
        p.sampled_s = now_s;
      }
      s.cpu_percent = p.cpu_percent;
    } else {
      p.sampled_pid = 0;
      p.cpu_percent = 0.0;
    }
    status.processes.push_back(std::move(s));
  }
  return status;
}

}  // namespace aslam
