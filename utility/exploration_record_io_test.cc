#include "utility/exploration_record_io.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;

class StateFile : public ::testing::Test {
 protected:
  void Write(const std::string& text) { std::ofstream(path_) << text; }
  std::string ErrorOf() {
    try {
      LoadExplorationRecord(path_);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  }
  const std::string path_ = TestTempPath("state.yaml");
};

TEST_F(StateFile, RoundTripsExactly) {
  ExplorationRecord record;
  record.decisions = 17;
  record.goals_reached = 9;
  record.goals_failed = 6;
  record.next_goal_id = 16;
  record.blacklist_m = {{1.0 / 3.0, -2.5}, {1e-9, 42.125}};
  record.retried_m = {{-7.75, 0.1}};
  Write(ExplorationRecordToYaml(record));
  EXPECT_TRUE(LoadExplorationRecord(path_) == record);
  Write(ExplorationRecordToYaml(ExplorationRecord{}));
  EXPECT_TRUE(LoadExplorationRecord(path_) == ExplorationRecord{});
  ExplorationRecord paused = record;
  paused.home_m = Point2d{-0.1, 1.0 / 7.0};
  paused.mode = ControlMode::kPaused;
  paused.paused_while_returning = true;
  Write(ExplorationRecordToYaml(paused));
  EXPECT_TRUE(LoadExplorationRecord(path_) == paused);
  ExplorationRecord ended = record;
  ended.mode = ControlMode::kEnded;
  ended.ends_done = true;
  ended.end_detail = "could not return: \"no path\": 3 tries";  // quotes and colons survive
  Write(ExplorationRecordToYaml(ended));
  EXPECT_TRUE(LoadExplorationRecord(path_) == ended);
}

// A state file written before EXPLORE_CONTROL loads as an exploration under way.
TEST_F(StateFile, FilesWithoutTheControlKeysLoad) {
  Write("decisions: 3\ngoals_reached: 1\ngoals_failed: 0\nnext_goal_id: 4\nblacklist_m: []\n");
  const ExplorationRecord record = LoadExplorationRecord(path_);
  EXPECT_EQ(record.next_goal_id, 4);
  EXPECT_FALSE(record.home_m.has_value());
  EXPECT_EQ(record.mode, ControlMode::kExploring);
}

TEST_F(StateFile, BadFilesAreErrorsNamingFileAndKey) {
  Write("decisions: 3\ngoals_reached: 1\ngoals_failed: 0\nblacklist_m: []\n");
  EXPECT_THAT(ErrorOf(), HasSubstr(path_));
  EXPECT_THAT(ErrorOf(), HasSubstr("next_goal_id"));
  Write("decisions: many\ngoals_reached: 1\ngoals_failed: 0\nnext_goal_id: 2\nblacklist_m: []\n");
  EXPECT_THAT(ErrorOf(), HasSubstr("decisions"));
  EXPECT_THAT(ErrorOf(), HasSubstr("many"));
  Write("decisions: 1\ngoals_reached: 1\ngoals_failed: 0\nnext_goal_id: 2\nblacklist_m: [[1]]\n");
  EXPECT_THAT(ErrorOf(), HasSubstr("blacklist_m"));
  Write("decisions: 1\ngoals_reached: -1\ngoals_failed: 0\nnext_goal_id: 2\nblacklist_m: []\n");
  EXPECT_THAT(ErrorOf(), HasSubstr(">= 0"));
  const std::string valid =
      "decisions: 1\ngoals_reached: 1\ngoals_failed: 0\nnext_goal_id: 2\n"
      "blacklist_m: []\n";
  Write(valid + "mode: sleeping\n");
  EXPECT_THAT(ErrorOf(), HasSubstr("mode"));
  EXPECT_THAT(ErrorOf(), HasSubstr("sleeping"));
  Write(valid + "mode: returning\n");  // the way home without a home
  EXPECT_THAT(ErrorOf(), HasSubstr("home_m"));
  Write(valid + "home_m: [1, .nan]\n");
  EXPECT_THAT(ErrorOf(), HasSubstr("home_m"));
  Write("decisions: [1\n");
  EXPECT_THAT(ErrorOf(), HasSubstr(path_));
}

}  // namespace
}  // namespace aslam
