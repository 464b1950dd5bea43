#include "drivers/sim/scripted_drive.h"

#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/config.h"
#include "common/test_temp_dir.h"

namespace aslam {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(ScriptedDrive, FollowsSegmentsThenEnds) {
  const ScriptedDrive drive({{1.0, 0.5, 0.0}, {0.5, 0.0, 1.0}});
  EXPECT_DOUBLE_EQ(drive.duration_s(), 1.5);
  EXPECT_DOUBLE_EQ(drive.CommandAt(0)->linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(drive.CommandAt(999'999)->linear_mps, 0.5);
  const auto turn = drive.CommandAt(1'000'000);
  ASSERT_TRUE(turn.has_value());
  EXPECT_DOUBLE_EQ(turn->linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(turn->angular_radps, 1.0);
  EXPECT_EQ(turn->utime, 1'000'000);
  EXPECT_FALSE(drive.CommandAt(1'500'000).has_value());
}

TEST(ScriptedDrive, RepeatsWhenAsked) {
  const ScriptedDrive drive({{1.0, 0.5, 0.0}, {1.0, 0.0, 1.0}}, /*repeat=*/true);
  EXPECT_DOUBLE_EQ(drive.CommandAt(2'200'000)->linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(drive.CommandAt(3'200'000)->angular_radps, 1.0);
  EXPECT_EQ(drive.CommandAt(3'200'000)->utime, 3'200'000);
}

class DriveFileTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) {
    std::ofstream(path_) << text;
    return path_;
  }
  const std::string path_ = TestTempPath("drive.yaml");
};

TEST_F(DriveFileTest, LoadsSegments) {
  const ScriptedDrive drive =
      LoadScriptedDrive(Write("repeat: true\nsegments:\n  - {duration_s: 2, linear_mps: 0.3}\n"
                              "  - {duration_s: 1, angular_radps: -0.5}\n"));
  ASSERT_EQ(drive.segments().size(), 2u);
  EXPECT_TRUE(drive.repeat());
  EXPECT_DOUBLE_EQ(drive.segments()[1].angular_radps, -0.5);
  EXPECT_DOUBLE_EQ(drive.duration_s(), 3.0);
}

TEST_F(DriveFileTest, BadFilesNameKeyAndValue) {
  const auto error = [&](const std::string& text) {
    try {
      LoadScriptedDrive(Write(text));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(error("segments:\n  - {duration_s: -1}\n"),
              AllOf(HasSubstr(path_), HasSubstr("segments[0].duration_s"), HasSubstr("'-1'")));
  EXPECT_THAT(error("segments:\n  - {linear_mps: 0.2}\n"), HasSubstr("needs a duration"));
  EXPECT_THAT(error("segments:\n  - {duration_s: 1, speed: 2}\n"),
              AllOf(HasSubstr("segments[0].speed"), HasSubstr("unknown key")));
  EXPECT_THAT(error("segments: []\n"), HasSubstr("at least one segment"));
  EXPECT_THAT(error("repeat: true\n"), HasSubstr("list of segments"));
  EXPECT_THAT(error("segments: [1, 2]\n"), HasSubstr("expected a mapping"));
}

}  // namespace
}  // namespace aslam
