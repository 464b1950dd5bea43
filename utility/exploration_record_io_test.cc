#include "utility/exploration_record_io.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
  const std::string path_ = std::filesystem::temp_directory_path() /
                            ("aslam_utility_state_" + std::to_string(::getpid()) + ".yaml");
  ~StateFile() override { std::filesystem::remove(path_); }
};

TEST_F(StateFile, RoundTripsExactly) {
  const ExplorationRecord record{17, 9, 6, 16, {{1.0 / 3.0, -2.5}, {1e-9, 42.125}}};
  Write(ExplorationRecordToYaml(record));
  EXPECT_TRUE(LoadExplorationRecord(path_) == record);
  Write(ExplorationRecordToYaml(ExplorationRecord{}));
  EXPECT_TRUE(LoadExplorationRecord(path_) == ExplorationRecord{});
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
  Write("decisions: [1\n");
  EXPECT_THAT(ErrorOf(), HasSubstr(path_));
}

}  // namespace
}  // namespace aslam
