#include "procman/procman_lcm.h"

namespace aslam {
namespace {

int8_t StateToLcm(ProcessState state) {
  switch (state) {
    case ProcessState::kRunning: return procman_process_status_t::STATE_RUNNING;
    case ProcessState::kStopping: return procman_process_status_t::STATE_STOPPING;
    case ProcessState::kBackoff: return procman_process_status_t::STATE_BACKOFF;
    case ProcessState::kFailed: return procman_process_status_t::STATE_FAILED;
    case ProcessState::kExited: return procman_process_status_t::STATE_EXITED;
    case ProcessState::kStopped: return procman_process_status_t::STATE_STOPPED;
  }
  return procman_process_status_t::STATE_STOPPED;
}

bool StateFromLcm(int8_t state, ProcessState* out) {
  switch (state) {
    case procman_process_status_t::STATE_STOPPED: *out = ProcessState::kStopped; return true;
    case procman_process_status_t::STATE_RUNNING: *out = ProcessState::kRunning; return true;
    case procman_process_status_t::STATE_BACKOFF: *out = ProcessState::kBackoff; return true;
    case procman_process_status_t::STATE_FAILED: *out = ProcessState::kFailed; return true;
    case procman_process_status_t::STATE_STOPPING: *out = ProcessState::kStopping; return true;
    case procman_process_status_t::STATE_EXITED: *out = ProcessState::kExited; return true;
    default: return false;
  }
}

}  // namespace

procman_status_t ToLcm(const DeputyStatus& status, int64_t utime) {
  procman_status_t message{};
  message.utime = utime;
  message.deputy = status.deputy;
  message.pid = status.pid;
  for (const auto& p : status.processes) {
    procman_process_status_t m{};
    m.name = p.name;
    m.group = p.group;
    m.command = p.command_line;
    m.should_run = p.should_run;
    m.state = StateToLcm(p.state);
    m.pid = p.pid;
    m.exit_code = p.exit_code;
    m.restarts = p.restarts;
    m.run_id = p.run_id;
    m.cpu_percent = p.cpu_percent;
    m.rss_bytes = p.rss_bytes;
    m.uptime_s = p.uptime_s;
    message.processes.push_back(std::move(m));
  }
  message.num_processes = static_cast<int32_t>(message.processes.size());
  return message;
}

bool FromLcm(const procman_status_t& message, DeputyStatus* status) {
  if (message.num_processes != static_cast<int32_t>(message.processes.size())) return false;
  DeputyStatus result;
  result.deputy = message.deputy;
  result.pid = message.pid;
  for (const auto& m : message.processes) {
    ProcessStatus p;
    if (m.name.empty() || !StateFromLcm(m.state, &p.state)) return false;
    p.name = m.name;
    p.group = m.group;
    p.command_line = m.command;
    p.should_run = m.should_run;
    p.pid = m.pid;
    p.exit_code = m.exit_code;
    p.restarts = m.restarts;
    p.run_id = m.run_id;
    p.cpu_percent = m.cpu_percent;
    p.rss_bytes = m.rss_bytes;
    p.uptime_s = m.uptime_s;
    result.processes.push_back(std::move(p));
  }
  *status = std::move(result);
  return true;
}

procman_orders_t ToLcm(const DeputyOrders& orders, int64_t utime, const std::string& sheriff) {
  procman_orders_t message{};
  message.utime = utime;
  message.deputy = orders.deputy;
  message.sheriff = sheriff;
  for (const auto& o : orders.processes) {
    procman_process_order_t m{};
    m.name = o.name;
    m.should_run = o.should_run;
    m.desired_run_id = o.run_id;
    message.processes.push_back(std::move(m));
  }
  message.num_processes = static_cast<int32_t>(message.processes.size());
  return message;
}

bool FromLcm(const procman_orders_t& message, DeputyOrders* orders) {
  if (message.num_processes != static_cast<int32_t>(message.processes.size())) return false;
  DeputyOrders result;
  result.deputy = message.deputy;
  for (const auto& m : message.processes) {
    if (m.name.empty()) return false;
    result.processes.push_back(ProcessOrder{m.name, m.should_run != 0, m.desired_run_id});
  }
  *orders = std::move(result);
  return true;
}

}  // namespace aslam
