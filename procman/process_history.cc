#include "procman/process_history.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "common/json_text.h"

namespace aslam {

void ProcessHistoryTracker::Add(const DeputyStatus& status) {
  for (const ProcessStatus& p : status.processes) {
    auto found = std::find_if(processes_.begin(), processes_.end(),
                              [&](const ProcessHistory& h) { return h.name == p.name; });
    if (found == processes_.end()) {
      ProcessHistory first_heard;
      first_heard.name = p.name;
      processes_.push_back(std::move(first_heard));
      found = processes_.end() - 1;
    }
    ProcessHistory& h = *found;
    // Stopping and stopped are the deputy's own doing; these states follow an end on its own
    // (running again with more restarts: the backoff status in between was missed).
    const bool ended_on_its_own = p.state == ProcessState::kBackoff ||
                                  p.state == ProcessState::kFailed ||
                                  p.state == ProcessState::kExited ||
                                  (p.state == ProcessState::kRunning && p.restarts > h.restarts);
    if (ended_on_its_own) {
      h.last_exit_code.reset();
      h.last_signal.reset();
      if (p.exit_code < 0) {
        h.last_signal = -p.exit_code;
      } else {
        h.last_exit_code = p.exit_code;
      }
    }
    h.restarts = std::max(h.restarts, p.restarts);
    h.state = p.state;
    h.should_run = p.should_run;
  }
}

std::optional<std::string> LostProcess(const std::vector<ProcessHistory>& processes,
                                       const std::string& expected_to_end) {
  for (const ProcessHistory& h : processes) {
    const std::string restarts =
        h.restarts > 0 ? " after " + std::to_string(h.restarts) + " restarts" : "";
    if (h.state == ProcessState::kFailed) {
      return h.name + " ended (" + LastEnd(h) + ")" + restarts + " and procman will not restart it";
    }
    if (h.state == ProcessState::kExited && h.name != expected_to_end) {
      return h.name + " exited with code 0" + restarts + " and procman will not restart it";
    }
  }
  return std::nullopt;
}

std::string SignalName(int signal) {
  const char* abbreviation = sigabbrev_np(signal);
  if (abbreviation == nullptr) return "signal " + std::to_string(signal);
  return std::string("SIG") + abbreviation;
}

std::string LastEnd(const ProcessHistory& process) {
  if (process.last_signal) return SignalName(*process.last_signal);
  if (process.last_exit_code) return "exit " + std::to_string(*process.last_exit_code);
  return "-";
}

std::string RestartsSummary(const std::vector<ProcessHistory>& processes) {
  std::string summary;
  for (const ProcessHistory& h : processes) {
    if (h.restarts == 0) continue;
    summary += (summary.empty() ? "" : ", ") + h.name + " " + std::to_string(h.restarts);
  }
  return summary;
}

std::vector<std::pair<std::string, std::string>> ProcessHistoryJsonFields(
    const ProcessHistory& process) {
  return {
      {"restarts", std::to_string(process.restarts)},
      {"last_exit_code", process.last_exit_code ? std::to_string(*process.last_exit_code) : "null"},
      {"last_signal", process.last_signal ? JsonString(SignalName(*process.last_signal)) : "null"},
  };
}

std::string ProcessHistoriesJson(const std::vector<ProcessHistory>& processes,
                                 const std::string& indent) {
  if (processes.empty()) return "{}";
  std::string json = "{";
  for (std::size_t i = 0; i < processes.size(); ++i) {
    json += (i == 0 ? "\n" : ",\n") + indent + "  " + JsonString(processes[i].name) + ": " +
            JsonObject(ProcessHistoryJsonFields(processes[i]));
  }
  return json + "\n" + indent + "}";
}

}  // namespace aslam
