#include "procman/deputy.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

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

// Appends `text` to the log at `path` (created); 0, or the errno of a log that cannot be
// opened. A failed write is not worth failing a start for.
int AppendToLog(const std::string& path, const std::string& text) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  close(fd);
  return 0;
}

}  // namespace

double SteadyClock::NowS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

const char* ProcessStateName(ProcessState state) {
  switch (state) {
    case ProcessState::kStopped: return "stopped";
    case ProcessState::kRunning: return "running";
    case ProcessState::kStopping: return "stopping";
    case ProcessState::kBackoff: return "backoff";
    case ProcessState::kFailed: return "failed";
    case ProcessState::kExited: return "exited";
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
    if (!p->should_run || p->child.running() || p->state == ProcessState::kStopping) continue;
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
  const std::string log_path = LogPath(p.config.name);
  const int log_errno =
      AppendToLog(log_path, "--- aslam-procman: start " + std::to_string(p.starts + 1) + " (run " +
                                std::to_string(p.run_id) + "): " + p.command_line + "\n");
  if (log_errno != 0) {
    p.state = ProcessState::kFailed;
    p.exit_code = 127;
    Fail(p, std::string("cannot start: ") + std::strerror(log_errno));
    return;
  }
  SubprocessOptions spawn;
  spawn.argv = {p.config.command};
  spawn.argv.insert(spawn.argv.end(), p.config.args.begin(), p.config.args.end());
  spawn.env = p.config.env;
  spawn.output_path = log_path;
  spawn.append_output = true;
  spawn.own_process_group = true;       // signals reach its children too
  spawn.parent_death_signal = SIGKILL;  // dies with the deputy, even if the deputy crashes
  try {
    p.child = Subprocess::Spawn(spawn);
  } catch (const SpawnError& e) {
    AppendToLog(log_path, std::string("--- aslam-procman: ") + e.what() + "\n");
    if (e.exec_failed()) {  // it was started, and ended at once
      ++p.starts;
      p.launch_at_s = -1.0;
      p.kill_sent = false;
      p.start_after_stop = false;
    }
    p.state = ProcessState::kFailed;  // a missing program does not appear by retrying
    p.exit_code = 127;
    Fail(p, e.what());
    return;
  }
  ++p.starts;
  p.launch_at_s = -1.0;
  p.kill_sent = false;
  p.start_after_stop = false;
  p.state = ProcessState::kRunning;
  p.started_s = now_s;
}

void Deputy::Stop(Process& p) {
  if (!p.child.running()) return;
  if (p.state != ProcessState::kStopping) {
    p.child.Signal(SIGTERM);
    p.state = ProcessState::kStopping;
    p.kill_at_s = clock_.NowS() + config_.stop_timeout_s;
    p.kill_sent = false;
  }
}

// Called once p.child has been reaped (its group's leftovers are killed by then).
void Deputy::OnExit(Process& p, const ExitStatus& status) {
  const bool stopping = p.state == ProcessState::kStopping;
  p.exit_code = status.CodeOrMinusSignal();
  const bool our_term = stopping && !p.kill_sent && status.signal == SIGTERM;
  const bool abnormal = p.exit_code != 0 && !our_term;
  const double now_s = clock_.NowS();
  if (abnormal)
    Fail(p, status.Describe() + (stopping && p.kill_sent ? " after the stop timeout" : ""));
  AppendToLog(LogPath(p.config.name), "--- aslam-procman: " + status.Describe() + "\n");
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
  const int give_up_after = p.config.backoff.give_up_after_failures;
  if (restart && abnormal && give_up_after > 0 && p.consecutive_failures + 1 >= give_up_after) {
    p.state = ProcessState::kFailed;
    const std::string reason = "gave up after " + std::to_string(give_up_after) +
                               " failures in a row (backoff.give_up_after_failures)";
    failure_reasons_.back() += "; " + reason;  // the same failure, not another
    AppendToLog(LogPath(p.config.name), "--- aslam-procman: " + reason + "\n");
  } else if (restart) {
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
    while (const auto reaped = ReapAnyChild()) {
      for (auto& p : processes_) {
        if (p.child.Claim(*reaped)) {
          OnExit(p, reaped->status);
          changed = true;
          break;
        }
      }  // anything else was an orphaned grandchild: reaped, nothing more to do
    }
  }
  for (auto& p : processes_) {
    if (!p.child.running()) continue;
    if (const auto status = p.child.Poll()) {
      OnExit(p, *status);
      changed = true;
    } else if (!p.child.running()) {
      // Not our child any more (cannot happen unless someone reaped it): forget it.
      p.state = ProcessState::kStopped;
      changed = true;
    }
  }
  const double now_s = clock_.NowS();
  for (auto& p : processes_) {
    if (p.state == ProcessState::kStopping && !p.kill_sent && now_s >= p.kill_at_s) {
      p.child.Signal(SIGKILL);
      p.kill_sent = true;
    }
    if (p.launch_at_s >= 0.0 && now_s >= p.launch_at_s && p.should_run && !shutting_down_ &&
        !p.child.running()) {
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
                                       [](const Process& p) { return !p.child.running(); });
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
    const pid_t pid = p.child.running() ? p.child.pid() : 0;
    s.pid = static_cast<int>(pid);
    s.exit_code = p.exit_code;
    s.restarts = std::max(0, p.starts - 1);
    s.run_id = p.run_id;
    if (pid > 0) {
      s.uptime_s = now_s - p.started_s;
      s.rss_bytes = RssBytes(pid);
      const long long ticks = CpuTicks(pid);
      if (p.sampled_pid != pid || ticks < 0) {
        p.cpu_percent = 0.0;
        p.sampled_pid = pid;
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
