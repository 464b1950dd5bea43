#include "common/lcm_util.h"

#include <cstdlib>
#include <stdexcept>

#include <gtest/gtest.h>

#include "aslam/odometry_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/cpu_time.h"
#include "common/inproc_host.h"

namespace aslam {
namespace {

TEST(ResolveLcmUrl, FlagThenEnvironmentThenDefault) {
  ::setenv("LCM_DEFAULT_URL", "memq://", 1);
  EXPECT_EQ(ResolveLcmUrl("udpm://239.255.76.67:7700?ttl=0"), "udpm://239.255.76.67:7700?ttl=0");
  EXPECT_EQ(ResolveLcmUrl(""), "memq://");
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(ResolveLcmUrl(""), kDefaultLcmUrl);
  EXPECT_NE(std::string(kDefaultLcmUrl).find("ttl=0"), std::string::npos);
}

TEST(OpenLcm, BadUrlThrowsNamingIt) {
  try {
    OpenLcm("nosuchprovider://x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://x"), std::string::npos);
  }
}

TEST(Subscriptions, DecodesHandlesAndCountsBadMessages) {
  InProcessHost host;
  Subscriptions subs(host.lcm());
  std::vector<double> speeds;
  subs.Add<velocity_command_t>("CMD_VEL", [&](const velocity_command_t& msg) {
    if (msg.linear_mps < 0) return false;  // the handler's own validation
    if (msg.linear_mps > 100) throw std::runtime_error("handler bug");
    speeds.push_back(msg.linear_mps);
    return true;
  });

  velocity_command_t good{};
  good.linear_mps = 0.3;
  host.lcm().publish("CMD_VEL", &good);
  const char garbage[] = "not an lcm message";
  host.lcm().publish("CMD_VEL", garbage, sizeof(garbage));
  odometry_t other_type{};  // a different type: fingerprint mismatch
  host.lcm().publish("CMD_VEL", &other_type);
  velocity_command_t invalid = good;
  invalid.linear_mps = -1;
  host.lcm().publish("CMD_VEL", &invalid);
  velocity_command_t throws = good;
  throws.linear_mps = 1000;
  host.lcm().publish("CMD_VEL", &throws);
  host.lcm().publish("CMD_VEL", &good);

  EXPECT_EQ(host.DispatchPending(), 6);
  EXPECT_EQ(speeds, (std::vector<double>{0.3, 0.3}));
  const ChannelStats& stats = subs.stats("CMD_VEL");
  EXPECT_EQ(stats.received, 2);
  EXPECT_EQ(stats.decode_failures, 2);
  EXPECT_EQ(stats.rejected, 1);
  EXPECT_EQ(stats.handler_errors, 1);
  EXPECT_EQ(subs.total_dropped(), 4);
  EXPECT_EQ(subs.stats("NO_SUCH_CHANNEL").received, 0);
}

TEST(Subscriptions, ChargesEachChannelTheCpuItsHandlerUsed) {
  InProcessHost host;
  Subscriptions subs(host.lcm());
  subs.Add<velocity_command_t>("BUSY", [](const velocity_command_t&) {
    const double until_s = ThreadCpuSeconds() + 0.02;
    while (ThreadCpuSeconds() < until_s) {
    }
    return true;
  });
  subs.Add<velocity_command_t>("IDLE", [](const velocity_command_t&) { return true; });
  velocity_command_t msg{};
  host.lcm().publish("BUSY", &msg);
  host.lcm().publish("IDLE", &msg);
  host.lcm().publish("BUSY", &msg);
  host.DispatchPending();

  const double busy_s = subs.stats("BUSY").cpu_s;
  EXPECT_GE(busy_s, 0.04);
  EXPECT_LT(subs.stats("IDLE").cpu_s, busy_s / 2);
  EXPECT_DOUBLE_EQ(subs.total_cpu_s(), busy_s + subs.stats("IDLE").cpu_s);
}

TEST(Subscriptions, UnsubscribesOnDestruction) {
  InProcessHost host;
  int calls = 0;
  {
    Subscriptions subs(host.lcm());
    subs.Add<velocity_command_t>("CMD_VEL", [&](const velocity_command_t&) { return ++calls > 0; });
    velocity_command_t msg{};
    host.lcm().publish("CMD_VEL", &msg);
    host.DispatchPending();
  }
  velocity_command_t msg{};
  host.lcm().publish("CMD_VEL", &msg);
  host.DispatchPending();
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace aslam
