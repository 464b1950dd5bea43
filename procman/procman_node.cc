#include "procman/procman_node.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>

#include "common/lcm_util.h"
#include "procman/procman_lcm.h"

namespace aslam {
namespace {

// One LCM wait: a signal interrupting it is not an error; a real failure is
// reported and slowed down so it cannot spin.
void HandleFor(lcm::LCM& lcm, int timeout_ms) {
  if (lcm.handleTimeout(timeout_ms) < 0 && errno != EINTR) {
    std::fprintf(stderr, "aslam-procman: LCM receive failed: %s\n", std::strerror(errno));
    usleep(timeout_ms * 1000);
  }
}

void PublishStatus(lcm::LCM& lcm, Deputy& deputy) {
  const procman_status_t message = ToLcm(deputy.Status(), WallClockUtime());
  lcm.publish(kProcmanStatusChannel, &message);
}

// Latest status of every deputy heard.
class StatusListener {
 public:
  explicit StatusListener(lcm::LCM& lcm) : lcm_(lcm), subscriptions_(lcm) {
    subscriptions_.Add<procman_status_t>(kProcmanStatusChannel,
                                         [this](const procman_status_t& message) {
                                           DeputyStatus status;
                                           if (!FromLcm(message, &status)) return false;
                                           deputies_[status.deputy] = std::move(status);
                                           ++received_;
                                           return true;
                                         });
  }
  // Handles LCM until `done` or `timeout_s`; returns `done()`.
  bool WaitFor(const std::function<bool()>& done, double timeout_s) {
    const double end_s = clock_.NowS() + timeout_s;
    while (!done()) {
      const double left_s = end_s - clock_.NowS();
      if (left_s <= 0) return false;
      HandleFor(lcm_, static_cast<int>(std::min(left_s, 0.05) * 1000) + 1);
    }
    return true;
  }
  const std::map<std::string, DeputyStatus>& deputies() const { return deputies_; }
  std::vector<DeputyStatus> All() const {
    std::vector<DeputyStatus> all;
    for (const auto& [name, status] : deputies_) all.push_back(status);
    return all;
  }
  int64_t received() const { return received_; }
  const SteadyClock& clock() const { return clock_; }

 private:
  lcm::LCM& lcm_;
  Subscriptions subscriptions_;
  SteadyClock clock_;
  std::map<std::string, DeputyStatus> deputies_;
  int64_t received_ = 0;
};

// Waits for a first status, then briefly for other deputies publishing in the same second.
bool HearDeputies(StatusListener& listener, const SheriffOptions& options) {
  if (!listener.WaitFor([&] { return listener.received() > 0; }, options.wait_s)) {
    std::fprintf(stderr,
                 "aslam-procman: no PROCMAN_STATUS heard within %.1f s; is a deputy "
                 "running on this LCM URL?\n",
                 options.wait_s);
    return false;
  }
  listener.WaitFor([] { return false; }, 0.3);
  return true;
}

}  // namespace

int RunDeputyNode(lcm::LCM& lcm, Deputy& deputy, const std::atomic<bool>& stop,
                  double status_period_s) {
  bool orders_changed = false;
  Subscriptions subscriptions(lcm);
  subscriptions.Add<procman_orders_t>(kProcmanOrdersChannel, [&](const procman_orders_t& message) {
    DeputyOrders orders;
    if (!FromLcm(message, &orders)) return false;
    orders_changed |= deputy.ApplyOrders(orders);
    return true;
  });
  const SteadyClock clock;
  deputy.Start();
  PublishStatus(lcm, deputy);
  double next_status_s = clock.NowS() + status_period_s;
  while (true) {
    if (stop.load() && !deputy.shutting_down()) {
      std::printf("aslam-procman: shutting down\n");
      std::fflush(stdout);
      deputy.BeginShutdown();
    }
    const bool changed = deputy.Step();
    if (deputy.Finished()) break;
    if (changed || orders_changed || clock.NowS() >= next_status_s) {
      PublishStatus(lcm, deputy);
      orders_changed = false;
      if (clock.NowS() >= next_status_s) next_status_s = clock.NowS() + status_period_s;
    }
    HandleFor(lcm, 20);  // bounds how late an exit is reaped and a signal noticed
  }
  PublishStatus(lcm, deputy);
  for (const auto& reason : deputy.failure_reasons()) {
    std::fprintf(stderr, "aslam-procman: failed: %s\n", reason.c_str());
  }
  std::printf("aslam-procman: stopped; %d failures, %lld orders ignored, %lld messages dropped\n",
              deputy.failures(), static_cast<long long>(deputy.ignored_orders()),
              static_cast<long long>(subscriptions.total_dropped()));
  std::fflush(stdout);
  return deputy.ExitCode();
}

int RunSheriffStatus(lcm::LCM& lcm, const SheriffOptions& options) {
  StatusListener listener(lcm);
  if (!HearDeputies(listener, options)) return 1;
  std::fputs(FormatStatusTable(listener.All()).c_str(), stdout);
  return 0;
}

int RunSheriffCommand(lcm::LCM& lcm, SheriffCommand command, const std::string& target,
                      const SheriffOptions& options) {
  StatusListener listener(lcm);
  if (!HearDeputies(listener, options)) return 1;
  std::vector<DeputyOrders> all_orders;
  for (const auto& [name, status] : listener.deputies()) {
    const std::vector<std::string> targets = MatchTargets(status, target);
    if (!targets.empty()) all_orders.push_back(ComputeOrders(status, command, targets));
  }
  if (all_orders.empty()) {
    std::string known;
    for (const auto& [name, status] : listener.deputies()) {
      for (const auto& p : status.processes)
        known += " " + p.name + (p.group.empty() ? "" : "(" + p.group + ")");
    }
    std::fprintf(stderr, "aslam-procman: no process or group named '%s'; known:%s\n",
                 target.c_str(), known.c_str());
    return 1;
  }
  const std::string sheriff = "sheriff-" + std::to_string(getpid());
  auto carried_out = [&] {
    for (const auto& orders : all_orders) {
      const auto found = listener.deputies().find(orders.deputy);
      if (found == listener.deputies().end() || !OrdersCarriedOut(found->second, orders)) {
        return false;
      }
    }
    return true;
  };
  // Whole desired state, five times over the first second and then each second:
  // a lost message costs nothing and a repeat changes nothing.
  const double start_s = listener.clock().NowS();
  bool done = false;
  for (int round = 0;; ++round) {
    for (const auto& orders : all_orders) {
      const procman_orders_t message = ToLcm(orders, WallClockUtime(), sheriff);
      lcm.publish(kProcmanOrdersChannel, &message);
    }
    const double left_s = options.wait_s - (listener.clock().NowS() - start_s);
    if (left_s <= 0 || (done && round >= 4)) break;
    if (round < 4) {
      listener.WaitFor([] { return false; }, std::min(left_s, 0.2));
      done = carried_out();
    } else {
      done = listener.WaitFor(carried_out, std::min(left_s, 1.0));
    }
  }
  done = carried_out();
  std::fputs(FormatStatusTable(listener.All()).c_str(), stdout);
  if (!done) {
    std::fprintf(stderr, "aslam-procman: orders not carried out within %.1f s\n", options.wait_s);
    return 1;
  }
  return 0;
}

}  // namespace aslam
