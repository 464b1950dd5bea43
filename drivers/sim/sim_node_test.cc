#include "drivers/sim/sim_node.h"

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aslam/lidar_scan_t.hpp"
#include "aslam/odometry_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/inproc_host.h"

namespace aslam {
namespace {

// A 10 m x 10 m room with 0.15 m walls, 0.05 m cells.
OccupancyGrid Room() {
  OccupancyGrid grid(200, 200, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int i = 0; i < 200; ++i) {
    for (int t = 0; t < 3; ++t) {
      grid.at({i, t}) = grid.at({i, 199 - t}) = grid.at({t, i}) = grid.at({199 - t, i}) = 100;
    }
  }
  return grid;
}

// Records every message on the bus, raw, in arrival order.
struct Recorder {
  struct Message {
    std::string channel;
    std::vector<uint8_t> bytes;
  };
  std::vector<Message> messages;
  std::map<std::string, int> counts;
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const auto* data = static_cast<const uint8_t*>(rbuf->data);
    messages.push_back({channel, {data, data + rbuf->data_size}});
    ++counts[channel];
  }
  template <typename Msg>
  std::vector<Msg> Decoded(const std::string& channel) const {
    std::vector<Msg> out;
    for (const auto& m : messages) {
      if (m.channel != channel) continue;
      Msg msg{};
      EXPECT_GT(msg.decode(m.bytes.data(), 0, m.bytes.size()), 0);
      out.push_back(msg);
    }
    return out;
  }
};

// Runs a SimNode for `seconds` of simulated time on memq, recording the bus.
Recorder RunRecorded(uint64_t seed, double seconds, std::optional<ScriptedDrive> drive = {}) {
  InProcessHost host;
  Recorder recorder;
  host.lcm().subscribe(".*", &Recorder::OnMessage, &recorder);
  SimulatorOptions options;
  options.seed = seed;
  Simulator simulator(Room(), {5.0, 5.0, 0.0}, options);
  SimNode node(host.lcm(), simulator, {"room", std::move(drive)});
  const int64_t end = static_cast<int64_t>(seconds * 1e6);
  host.Run([&] {
    if (node.utime() >= end) return false;
    node.Tick();
    return true;
  });
  return recorder;
}

TEST(SimNode, PublishesEveryChannelAtItsRate) {
  const Recorder rec = RunRecorded(1, 10.0);
  EXPECT_EQ(rec.counts.at("LIDAR_SCAN"), 100);
  EXPECT_EQ(rec.counts.at("ODOMETRY"), 500);
  EXPECT_EQ(rec.counts.at("SIM_TRUTH"), 500);
  EXPECT_EQ(rec.counts.at("SIM_STATUS"), 10);
  const auto scans = rec.Decoded<lidar_scan_t>("LIDAR_SCAN");
  EXPECT_EQ(scans.front().num_ranges, 720);
  EXPECT_EQ(scans.front().utime, 100'000);
  EXPECT_EQ(scans.back().seq, 99);
  const auto truth = rec.Decoded<pose_t>("SIM_TRUTH");
  EXPECT_EQ(truth.front().frame, "world");
}

TEST(SimNode, OdometryPrecedesTheScanOfTheSameTime) {
  const Recorder rec = RunRecorded(1, 2.0);
  int64_t last_odometry_utime = -1;
  int scans = 0;
  for (const auto& m : rec.messages) {
    if (m.channel == "ODOMETRY") {
      odometry_t msg{};
      msg.decode(m.bytes.data(), 0, m.bytes.size());
      last_odometry_utime = msg.utime;
    } else if (m.channel == "LIDAR_SCAN") {
      lidar_scan_t msg{};
      msg.decode(m.bytes.data(), 0, m.bytes.size());
      EXPECT_EQ(last_odometry_utime, msg.utime);
      ++scans;
    }
  }
  EXPECT_EQ(scans, 20);
}

TEST(SimNode, SameSeedGivesBitIdenticalMessagesAndOtherSeedsDiffer) {
  const ScriptedDrive drive({{2.0, 0.4, 0.3}, {1.0, 0.0, -1.0}});
  const Recorder a = RunRecorded(11, 3.0, drive);
  const Recorder b = RunRecorded(11, 3.0, drive);
  const Recorder c = RunRecorded(12, 3.0, drive);
  ASSERT_EQ(a.messages.size(), b.messages.size());
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    ASSERT_EQ(a.messages[i].channel, b.messages[i].channel) << i;
    ASSERT_EQ(a.messages[i].bytes, b.messages[i].bytes) << a.messages[i].channel << " #" << i;
  }
  ASSERT_EQ(a.messages.size(), c.messages.size());
  int differing_scans = 0;
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    if (a.messages[i].channel == "LIDAR_SCAN" && a.messages[i].bytes != c.messages[i].bytes) {
      ++differing_scans;
    }
  }
  EXPECT_EQ(differing_scans, 30);
}

// A controller node on the same bus: answers each odometry message with a
// command, as the navigator will. The robot must move, then stop once the
// commands stop and go stale.
TEST(SimNode, FollowsCmdVelAndStopsWhenCommandsGoStale) {
  InProcessHost host;
  Simulator simulator(Room(), {2.0, 5.0, 0.0}, SimulatorOptions{});
  SimNode node(host.lcm(), simulator, {"room", std::nullopt});
  Subscriptions controller(host.lcm());
  bool commanding = true;
  controller.Add<odometry_t>("ODOMETRY", [&](const odometry_t& odometry) {
    if (!commanding) return true;
    velocity_command_t cmd{};
    cmd.utime = odometry.utime;
    cmd.linear_mps = 0.5;
    host.lcm().publish("CMD_VEL", &cmd);
    return true;
  });
  std::vector<sim_status_t> statuses;
  Subscriptions status_listener(host.lcm());
  status_listener.Add<sim_status_t>("SIM_STATUS", [&](const sim_status_t& s) {
    statuses.push_back(s);
    return true;
  });

  host.Run([&] {
    if (node.utime() >= 4'000'000) return false;
    node.Tick();
    return true;
  });
  const double x_after_driving = simulator.true_pose().x_m;
  EXPECT_GT(x_after_driving, 3.5);  // 4 s at up to 0.5 m/s after a 0.5 s ramp
  EXPECT_FALSE(simulator.command_stale());

  commanding = false;
  host.Run([&] {
    if (node.utime() >= 6'000'000) return false;
    node.Tick();
    return true;
  });
  EXPECT_TRUE(simulator.command_stale());
  EXPECT_DOUBLE_EQ(simulator.true_velocity().linear_mps, 0.0);
  EXPECT_LT(simulator.true_pose().x_m - x_after_driving, 0.5 * 0.5 + 0.15);
  ASSERT_FALSE(statuses.empty());
  EXPECT_GT(statuses.back().commands_received, 150);
  EXPECT_TRUE(statuses.back().command_stale);
  EXPECT_EQ(statuses.back().collisions, 0);
}

TEST(SimNode, BadCommandsAreDroppedAndCounted) {
  InProcessHost host;
  Simulator simulator(Room(), {5.0, 5.0, 0.0}, SimulatorOptions{});
  SimNode node(host.lcm(), simulator, {"room", std::nullopt});
  const char garbage[] = "garbage";
  host.lcm().publish("CMD_VEL", garbage, sizeof(garbage));
  velocity_command_t nan_command{};
  nan_command.linear_mps = std::numeric_limits<double>::quiet_NaN();
  host.lcm().publish("CMD_VEL", &nan_command);
  std::optional<sim_status_t> status;
  Subscriptions listener(host.lcm());
  listener.Add<sim_status_t>("SIM_STATUS", [&](const sim_status_t& s) {
    status = s;
    return true;
  });
  host.DispatchPending();
  host.Run([&] {
    if (node.utime() >= 1'000'000) return false;
    node.Tick();
    return true;
  });
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->messages_dropped, 2);
  EXPECT_EQ(status->commands_received, 0);
  EXPECT_DOUBLE_EQ(simulator.true_pose().x_m, 5.0);
}

TEST(SimNode, ScriptedDriveIsFollowedAndEnds) {
  InProcessHost host;
  Simulator simulator(Room(), {2.0, 5.0, 0.0}, SimulatorOptions{});
  SimNode node(host.lcm(), simulator, {"room", ScriptedDrive({{3.0, 0.5, 0.0}})});
  host.Run([&] {
    if (node.drive_finished()) return false;
    node.Tick();
    return true;
  });
  EXPECT_EQ(node.utime(), 3'000'000);
  // 3 s at 0.5 m/s with a 0.5 s ramp up at 1 m/s^2: 1.375 m.
  EXPECT_NEAR(simulator.true_pose().x_m, 2.0 + 1.375, 0.02);
}

}  // namespace
}  // namespace aslam
