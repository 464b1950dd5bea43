#include "procman/sheriff.h"

#include <algorithm>
#include <cstdio>

namespace aslam {

bool ParseSheriffCommand(const std::string& text, SheriffCommand* command) {
  if (text == "start")
    *command = SheriffCommand::kStart;
  else if (text == "stop")
    *command = SheriffCommand::kStop;
  else if (text == "restart")
    *command = SheriffCommand::kRestart;
  else
    return false;
  return true;
}

std::vector<std::string> MatchTargets(const DeputyStatus& status, const std::string& target) {
  for (const auto& p : status.processes) {
    if (p.name == target) return {p.name};
  }
  std::vector<std::string> names;
  for (const auto& p : status.processes) {
    if (!p.group.empty() && p.group == target) names.push_back(p.name);
  }
  return names;
}

DeputyOrders ComputeOrders(const DeputyStatus& status, SheriffCommand command,
                           const std::vector<std::string>& targets) {
  DeputyOrders orders;
  orders.deputy = status.deputy;
  for (const auto& p : status.processes) {
    ProcessOrder order{p.name, p.should_run, p.run_id};
    if (std::find(targets.begin(), targets.end(), p.name) != targets.end()) {
      const bool running = p.pid != 0 && p.state == ProcessState::kRunning;
      switch (command) {
        case SheriffCommand::kStart:
          order.should_run = true;
          if (!running) ++order.run_id;
          break;
        case SheriffCommand::kStop: order.should_run = false; break;
        case SheriffCommand::kRestart:
          order.should_run = true;
          ++order.run_id;
          break;
      }
    }
    orders.processes.push_back(order);
  }
  return orders;
}

bool OrdersCarriedOut(const DeputyStatus& status, const DeputyOrders& orders) {
  for (const auto& order : orders.processes) {
    const auto p = std::find_if(status.processes.begin(), status.processes.end(),
                                [&](const ProcessStatus& s) { return s.name == order.name; });
    if (p == status.processes.end()) return false;
    if (p->should_run != order.should_run || p->state == ProcessState::kStopping) return false;
    if (!order.should_run && p->pid != 0) return false;
    if (order.should_run && p->run_id != order.run_id) return false;
  }
  return true;
}

std::string FormatStatusTable(const std::vector<DeputyStatus>& deputies) {
  std::string table;
  char line[512];
  for (const auto& d : deputies) {
    std::snprintf(line, sizeof line, "deputy %s (pid %d)\n", d.deputy.c_str(), d.pid);
    table += line;
    std::snprintf(line, sizeof line, "%-16s %-12s %-9s %8s %8s %5s %7s %9s\n", "name", "group",
                  "state", "pid", "restarts", "exit", "cpu%", "rss_MB");
    table += line;
    for (const auto& p : d.processes) {
      std::snprintf(line, sizeof line, "%-16s %-12s %-9s %8d %8d %5d %7.1f %9.1f\n", p.name.c_str(),
                    p.group.empty() ? "-" : p.group.c_str(), ProcessStateName(p.state), p.pid,
                    p.restarts, p.exit_code, p.cpu_percent, p.rss_bytes / 1e6);
      table += line;
    }
  }
  return table;
}

}  // namespace aslam
