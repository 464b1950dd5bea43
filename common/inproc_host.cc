#include "common/inproc_host.h"

#include <cstdio>
#include <cstdlib>

namespace aslam {

InProcessHost::InProcessHost() : lcm_("memq://") {
  if (!lcm_.good()) {
    std::fprintf(stderr, "InProcessHost: cannot open memq://\n");
    std::abort();
  }
}

int64_t InProcessHost::DispatchPending() {
  int64_t handled = 0;
  // memq queues synchronously on publish, so a zero timeout sees everything pending.
  while (lcm_.handleTimeout(0) > 0) ++handled;
  messages_dispatched_ += handled;
  return handled;
}

int64_t InProcessHost::Run(const std::function<bool()>& tick,
                           const std::function<bool()>& keep_running) {
  int64_t ticks = 0;
  while (tick()) {
    ++ticks;
    DispatchPending();
    if (!keep_running()) break;
  }
  return ticks;
}

}  // namespace aslam
