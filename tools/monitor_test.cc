#include "tools/monitor.h"

#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "aslam/sim_status_t.hpp"
#include "aslam/velocity_command_t.hpp"

namespace aslam {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

template <typename Msg>
std::vector<uint8_t> Encode(const Msg& msg) {
  std::vector<uint8_t> bytes(msg.getEncodedSize());
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

void Feed(BusMonitor* monitor, const std::string& channel, const std::vector<uint8_t>& bytes) {
  monitor->OnMessage(channel, bytes.data(), static_cast<int>(bytes.size()));
}

TEST(BusMonitor, CountsMessagesRatesAndTypesPerChannel) {
  BusMonitor monitor;
  const std::vector<uint8_t> command = Encode(velocity_command_t{});
  for (int i = 0; i < 4; ++i) Feed(&monitor, "CMD_VEL", command);
  Feed(&monitor, "MYSTERY", std::vector<uint8_t>(16, 0xab));  // fingerprint of no aslam type
  Feed(&monitor, "SHORT", std::vector<uint8_t>(3, 0));        // too short for a fingerprint
  EXPECT_EQ(monitor.total_messages(), 6);

  const std::string report = monitor.Report(2.0, 10.0);
  EXPECT_THAT(report, HasSubstr("--- 10.0 s: 3 channels\n"));
  // 4 messages in a 2 s window: 2 Hz.
  EXPECT_THAT(report,
              HasSubstr("CMD_VEL          aslam.velocity_command_t             4      2.0"));
  EXPECT_THAT(report, HasSubstr("MYSTERY          unknown"));
  EXPECT_THAT(report, HasSubstr("SHORT            ?"));
  EXPECT_THAT(report, Not(HasSubstr("sim:")));

  // The next report's rates cover only its own window; the totals keep counting.
  Feed(&monitor, "CMD_VEL", command);
  const std::string next = monitor.Report(1.0, 11.0);
  EXPECT_THAT(next, HasSubstr("CMD_VEL          aslam.velocity_command_t             5      1.0"));
  EXPECT_THAT(next, HasSubstr("MYSTERY          unknown                              1      0.0"));
}

TEST(BusMonitor, IgnoresTheSelfTestAndShowsTheLatestSimStatus) {
  BusMonitor monitor;
  Feed(&monitor, "LCM_SELF_TEST", std::vector<uint8_t>(16, 0));
  EXPECT_EQ(monitor.total_messages(), 0);
  sim_status_t status{};
  status.utime = 12'500'000;
  status.real_time_factor = 3.0;
  status.collisions = 2;
  status.scans_published = 125;
  status.messages_dropped = 1;
  Feed(&monitor, "SIM_STATUS", Encode(status));
  status.utime = 13'500'000;
  Feed(&monitor, "SIM_STATUS", Encode(status));
  const std::string report = monitor.Report(1.0, 1.0);
  EXPECT_THAT(report, HasSubstr("--- 1.0 s: 1 channels\n"));
  EXPECT_THAT(report, Not(HasSubstr("LCM_SELF_TEST")));
  EXPECT_THAT(report, HasSubstr("SIM_STATUS       aslam.sim_status_t"));
  EXPECT_THAT(report,
              HasSubstr("sim: t=13.5 s  x3.0 real time  collisions=2  scans=125  dropped=1\n"));
}

}  // namespace
}  // namespace aslam
