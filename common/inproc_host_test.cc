#include "common/inproc_host.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aslam/velocity_command_t.hpp"
#include "common/lcm_util.h"

namespace aslam {
namespace {

// Two toy nodes: a "source" ticked by the host publishes A at each tick; a
// relay answers every A with a B. Each tick's B must be handled before the
// next tick, in publish order.
TEST(InProcessHost, DispatchesEverythingInOrderBeforeTheNextTick) {
  InProcessHost host;
  std::vector<std::string> events;
  Subscriptions relay(host.lcm());
  relay.Add<velocity_command_t>("A", [&](const velocity_command_t& msg) {
    events.push_back("A" + std::to_string(msg.utime));
    velocity_command_t reply = msg;
    host.lcm().publish("B", &reply);
    return true;
  });
  Subscriptions sink(host.lcm());
  sink.Add<velocity_command_t>("B", [&](const velocity_command_t& msg) {
    events.push_back("B" + std::to_string(msg.utime));
    return true;
  });

  int64_t now = 0;
  const int64_t ticks = host.Run([&] {
    if (now == 3) return false;
    events.push_back("tick" + std::to_string(++now));
    for (int k = 0; k < 2; ++k) {
      velocity_command_t msg{};
      msg.utime = now * 10 + k;
      host.lcm().publish("A", &msg);
    }
    return true;
  });

  EXPECT_EQ(ticks, 3);
  const std::vector<std::string> expected = {"tick1", "A10", "A11", "B10", "B11",  //
                                             "tick2", "A20", "A21", "B20", "B21",  //
                                             "tick3", "A30", "A31", "B30", "B31"};
  EXPECT_EQ(events, expected);
  EXPECT_EQ(host.messages_dispatched(), 12);
}

TEST(InProcessHost, StopsWhenKeepRunningSaysSo) {
  InProcessHost host;
  int ticks_seen = 0;
  const int64_t ticks =
      host.Run([&] { return ++ticks_seen < 100; }, [&] { return ticks_seen < 5; });
  EXPECT_EQ(ticks, 5);
}

TEST(InProcessHost, DispatchPendingWithNothingQueuedReturnsZero) {
  InProcessHost host;
  EXPECT_EQ(host.DispatchPending(), 0);
}

}  // namespace
}  // namespace aslam
