#include "common/lcm_util.h"

#include <cstdlib>
#include <stdexcept>

#include <gtest/gtest.h>

#include "aslam/odometry_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
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

// A channel carrying a type and its legacy twin: each message reaches its own type's handler.
TEST(Subscriptions, AddWithLegacyDispatchesByFingerprint) {
  InProcessHost host;
  Subscriptions subs(host.lcm());
  std::vector<double> speeds;
  std::vector<double> odometry_x;
  subs.AddWithLegacy<velocity_command_t, odometry_t>(
      "MIXED",
      [&](const velocity_command_t& msg) {
        speeds.push_back(msg.linear_mps);
        return true;
      },
      [&](const odometry_t& msg) {
        odometry_x.push_back(msg.pose.x_m);
        return msg.pose.x_m >= 0.0;
      });

  velocity_command_t command{};
  command.linear_mps = 0.25;
  host.lcm().publish("MIXED", &command);
  odometry_t odometry{};
  odometry.pose.x_m = 1.5;
  host.lcm().publish("MIXED", &odometry);
  odometry.pose.x_m = -1.0;  // the legacy handler's own refusal
  host.lcm().publish("MIXED", &odometry);
  pose_t neither{};
  host.lcm().publish("MIXED", &neither);
  const char short_garbage[] = "abc";
  host.lcm().publish("MIXED", short_garbage, sizeof(short_garbage));
  // The legacy fingerprint followed by too few bytes: a decode failure, not the other type.
  std::vector<uint8_t> truncated(static_cast<std::size_t>(odometry.getEncodedSize()));
  ASSERT_GT(odometry.encode(truncated.data(), 0, static_cast<int>(truncated.size())), 0);
  truncated.resize(12);
  host.lcm().publish("MIXED", truncated.data(), static_cast<unsigned>(truncated.size()));

  EXPECT_EQ(host.DispatchPending(), 6);
  EXPECT_EQ(speeds, (std::vector<double>{0.25}));
  EXPECT_EQ(odometry_x, (std::vector<double>{1.5, -1.0}));
  const ChannelStats& stats = subs.stats("MIXED");
  EXPECT_EQ(stats.received, 2);
  EXPECT_EQ(stats.rejected, 1);
  EXPECT_EQ(stats.decode_failures, 3);
}

// lcm-gen's decoders resize arrays to the count they read before reading the elements, and
// throw on an empty string length; lcmtypes/guard_array_counts.cmake makes both refusals.
TEST(Subscriptions, ImpossibleCountsAndLengthsAreDecodeFailures) {
  pose_graph_t graph{};
  std::vector<uint8_t> bytes(graph.getEncodedSize());
  ASSERT_EQ(graph.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  // num_edges is the last field (no edges follow): claim 2^31 - 1 of them, then -5.
  for (const uint32_t count : {0x7fffffffu, 0xfffffffbu}) {
    for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + i] = (count >> (24 - 8 * i)) & 0xff;
    pose_graph_t decoded;
    EXPECT_LT(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
    EXPECT_TRUE(decoded.edges.empty());
  }

  // A string whose length (which counts its NUL) is 0 or negative.
  pose_t pose{};
  pose.frame = "map";
  std::vector<uint8_t> pose_bytes(pose.getEncodedSize());
  ASSERT_GT(pose.encode(pose_bytes.data(), 0, static_cast<int>(pose_bytes.size())), 0);
  for (const uint32_t length : {0u, 0xfffffff0u}) {
    for (int i = 0; i < 4; ++i) pose_bytes[8 + 8 + i] = (length >> (24 - 8 * i)) & 0xff;
    pose_t decoded;
    EXPECT_LT(decoded.decode(pose_bytes.data(), 0, static_cast<int>(pose_bytes.size())), 0);
  }

  InProcessHost host;
  Subscriptions subs(host.lcm());
  int handled = 0;
  subs.Add<pose_graph_t>("POSE_GRAPH", [&](const pose_graph_t&) { return ++handled > 0; });
  host.lcm().publish("POSE_GRAPH", bytes.data(), static_cast<unsigned>(bytes.size()));
  host.DispatchPending();
  EXPECT_EQ(handled, 0);
  EXPECT_EQ(subs.stats("POSE_GRAPH").decode_failures, 1);
  EXPECT_EQ(subs.stats("POSE_GRAPH").handler_errors, 0);
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
