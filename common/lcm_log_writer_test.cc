#include "common/lcm_log_writer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "aslam/velocity_command_t.hpp"
#include "common/test_temp_dir.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

TEST(LcmLogWriter, WritesEventsInOrderThatLcmReadsBack) {
  const std::string path = TestTempPath("test.lcmlog");
  velocity_command_t command{};
  command.utime = 42;
  command.linear_mps = 0.25;
  command.angular_radps = -1.5;
  {
    LcmLogWriter log(path);
    log.Write("CMD_VEL", 1'000, command);
    const uint8_t bytes[] = {7, 8, 9};
    log.WriteBytes("RAW", 2'000, bytes, 3);
    EXPECT_EQ(log.events(), 2);
  }

  lcm::LogFile log(path, "r");
  ASSERT_TRUE(log.good());
  const lcm::LogEvent* first = log.readNextEvent();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->eventnum, 0);
  EXPECT_EQ(first->timestamp, 1'000);
  EXPECT_EQ(first->channel, "CMD_VEL");
  velocity_command_t decoded{};
  ASSERT_EQ(decoded.decode(first->data, 0, first->datalen), first->datalen);
  EXPECT_EQ(decoded.utime, 42);
  EXPECT_EQ(decoded.linear_mps, 0.25);
  EXPECT_EQ(decoded.angular_radps, -1.5);

  const lcm::LogEvent* second = log.readNextEvent();
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->eventnum, 1);
  EXPECT_EQ(second->timestamp, 2'000);
  EXPECT_EQ(second->channel, "RAW");
  ASSERT_EQ(second->datalen, 3);
  EXPECT_EQ(static_cast<const uint8_t*>(second->data)[2], 9);
  EXPECT_EQ(log.readNextEvent(), nullptr);
}

TEST(LcmLogWriter, AnUnwritablePathIsNamed) {
  try {
    LcmLogWriter log("/nonexistent-folder/x.lcmlog");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent-folder/x.lcmlog"));
  }
}

}  // namespace
}  // namespace aslam
