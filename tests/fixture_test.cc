// logs/test_drive.lcmlog (30 s of aslam-sim on a scripted drive in
// worlds/test, recorded with lcm-logger by logs/record_test_drive.sh): every
// message decodes as its channel's type and time never runs backwards.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "aslam/odometry_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "common/types_lcm.h"

namespace aslam {
namespace {

const std::string kFixture = std::string(ASLAM_SOURCE_DIR) + "/logs/test_drive.lcmlog";

// Decodes one event as Msg; returns its utime, or -1 if it does not decode.
template <typename Msg>
int64_t DecodeUtime(const lcm::LogEvent& event, Msg* msg) {
  const int used = msg->decode(event.data, 0, event.datalen);
  return used == event.datalen ? msg->utime : -1;
}

TEST(Fixture, EveryMessageDecodesAndTimeNeverRunsBackwards) {
  lcm::LogFile log(kFixture, "r");
  ASSERT_TRUE(log.good()) << "cannot open " << kFixture;

  std::map<std::string, int> counts;
  std::map<std::string, int64_t> last_utime;
  int64_t last_log_timestamp = -1;
  int undecodable = 0;
  int invalid = 0;
  std::optional<LidarScan> last_scan;

  for (const lcm::LogEvent* event = log.readNextEvent(); event != nullptr;
       event = log.readNextEvent()) {
    EXPECT_GE(event->timestamp, last_log_timestamp) << "log timestamps run backwards";
    last_log_timestamp = event->timestamp;
    const std::string channel = event->channel;
    int64_t utime = -1;
    if (channel == "LIDAR_SCAN") {
      // The fixtures predate beam times: they exercise the legacy wire type too.
      last_scan = DecodeLidarScan(event->data, event->datalen);
      utime = last_scan ? last_scan->utime : -1;
    } else if (channel == "ODOMETRY") {
      odometry_t msg{};
      utime = DecodeUtime(*event, &msg);
      if (utime >= 0 && !FromLcm(msg)) ++invalid;
    } else if (channel == "SIM_TRUTH") {
      pose_t msg{};
      utime = DecodeUtime(*event, &msg);
      if (utime >= 0 && (!FromLcm(msg) || msg.frame != "world")) ++invalid;
    } else if (channel == "SIM_STATUS") {
      sim_status_t msg{};
      utime = DecodeUtime(*event, &msg);
      if (utime >= 0) {
        EXPECT_EQ(msg.collisions, 0) << "the recorded drive touched a wall";
      }
    } else {
      ADD_FAILURE() << "unexpected channel " << channel;
      continue;
    }
    if (utime < 0) {
      ++undecodable;
      continue;
    }
    auto [it, first] = last_utime.emplace(channel, utime);
    if (!first) {
      EXPECT_GT(utime, it->second) << channel << " utime runs backwards or repeats";
      it->second = utime;
    }
    ++counts[channel];
  }

  EXPECT_EQ(undecodable, 0);
  EXPECT_EQ(invalid, 0);
  // 30 s at 10 Hz scans, 50 Hz odometry and truth, 1 Hz status; a few may
  // be lost at the ends of the recording.
  EXPECT_GE(counts["LIDAR_SCAN"], 280);
  EXPECT_GE(counts["ODOMETRY"], 1400);
  EXPECT_GE(counts["SIM_TRUTH"], 1400);
  EXPECT_GE(counts["SIM_STATUS"], 28);
  ASSERT_TRUE(last_scan.has_value());
  EXPECT_EQ(last_scan->range_m.size(), 720u);
}

}  // namespace
}  // namespace aslam
