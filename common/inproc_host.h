#pragma once

// The in-process hosting of docs/architecture.md §4: every node on one memq:// LCM, the
// simulator driving the clock. After each tick the host dispatches every
// pending message (including those published while dispatching) before the
// next tick, so a run is deterministic and as fast as the CPU allows.

#include <cstdint>
#include <functional>

#include <lcm/lcm-cpp.hpp>

namespace aslam {

class InProcessHost {
 public:
  InProcessHost();  // aborts if memq:// cannot be opened (it has no failure modes)
  InProcessHost(const InProcessHost&) = delete;
  InProcessHost& operator=(const InProcessHost&) = delete;

  // The bus every hosted node subscribes and publishes on.
  lcm::LCM& lcm() { return lcm_; }

  // Handles messages until none is pending; returns how many were handled.
  int64_t DispatchPending();

  // Calls `tick` (which advances the clock and publishes), then dispatches,
  // until `tick` returns false or `keep_running` (checked after each
  // dispatch) returns false. Returns the number of ticks run.
  int64_t Run(
      const std::function<bool()>& tick,
      const std::function<bool()>& keep_running = [] { return true; });

  int64_t messages_dispatched() const { return messages_dispatched_; }

 private:
  lcm::LCM lcm_;
  int64_t messages_dispatched_ = 0;
};

}  // namespace aslam
