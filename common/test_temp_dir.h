#pragma once

// Where tests write files. ctest runs every test case as its own process, several at once, so a
// fixed name in the shared temp folder is a race between cases: each case gets its own folder.

#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <system_error>

#include <gtest/gtest.h>

namespace aslam {
namespace test_temp_dir_internal {

// The folders this process made, removed at exit by this process only (a forked child that
// exits must not take its parent's files).
class MadeFolders {
 public:
  MadeFolders() : owner_pid_(::getpid()) {}
  ~MadeFolders() {
    if (::getpid() != owner_pid_) return;
    std::error_code ignored;
    for (const std::string& folder : folders_) std::filesystem::remove_all(folder, ignored);
  }
  // True the first time `folder` is added.
  bool Add(const std::string& folder) { return folders_.insert(folder).second; }

 private:
  pid_t owner_pid_;
  std::set<std::string> folders_;
};

}  // namespace test_temp_dir_internal

// The running test case's own folder, named for the case and the process: empty when the case
// first asks, removed when the process exits.
inline std::string TestTempDir() {
  static test_temp_dir_internal::MadeFolders made;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test =
      info == nullptr ? "none" : std::string(info->test_suite_name()) + "." + info->name();
  const std::string folder = (std::filesystem::path(::testing::TempDir()) /
                              ("aslam_" + test + "_" + std::to_string(::getpid())))
                                 .string();
  if (made.Add(folder)) {
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
  }
  return folder;
}

// The path of a file named `name` in TestTempDir().
inline std::string TestTempPath(const std::string& name) { return TestTempDir() + "/" + name; }

// An empty folder named `name` in TestTempDir(), emptied if it was there; returns its path.
inline std::string FreshTestTempDir(const std::string& name) {
  const std::string folder = TestTempPath(name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

}  // namespace aslam
