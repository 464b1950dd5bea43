#include "common/atomic_file.h"

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> Entries(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  return names;
}

// The message of what `write` throws; "" if it throws nothing.
template <typename F>
std::string ErrorOf(F write) {
  try {
    write();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(WriteFileAtomicallyTest, WritesAndReplacesLeavingNoTemporaryFile) {
  const std::string folder = FreshTestTempDir("replace");
  const std::string path = folder + "/metrics.json";
  WriteFileAtomically(path, "a longer first version\n");
  EXPECT_EQ(ReadAll(path), "a longer first version\n");
  WriteFileAtomically(path, std::string("short\0binary", 12));
  EXPECT_EQ(ReadAll(path), std::string("short\0binary", 12));
  EXPECT_EQ(Entries(folder), std::vector<std::string>{"metrics.json"});
  struct stat info {};
  ASSERT_EQ(stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0644u);
}

TEST(WriteFileAtomicallyTest, EmptyContentAndARelativePath) {
  const std::string folder = FreshTestTempDir("relative");
  const fs::path before = fs::current_path();
  fs::current_path(folder);
  WriteFileAtomically("empty.csv", "");
  fs::current_path(before);
  EXPECT_TRUE(fs::exists(folder + "/empty.csv"));
  EXPECT_EQ(fs::file_size(folder + "/empty.csv"), 0u);
  EXPECT_EQ(Entries(folder), std::vector<std::string>{"empty.csv"});
}

// Root may write anywhere, so "unwritable" here is a folder that is missing or is a file.
TEST(WriteFileAtomicallyTest, UnwritableFolderNamesThePathAndTheReason) {
  const std::string folder = FreshTestTempDir("unwritable");
  const std::string missing = folder + "/no/such/folder/map.yaml";
  EXPECT_THAT(ErrorOf([&] { WriteFileAtomically(missing, "x"); }),
              AllOf(HasSubstr(missing), HasSubstr(std::strerror(ENOENT))));
  WriteFileAtomically(folder + "/file", "x");
  const std::string under_file = folder + "/file/map.yaml";
  EXPECT_THAT(ErrorOf([&] { WriteFileAtomically(under_file, "x"); }),
              AllOf(HasSubstr(under_file), HasSubstr(std::strerror(ENOTDIR))));
  EXPECT_EQ(Entries(folder), std::vector<std::string>{"file"});
}

// A write that fails half-way (the file size limit, as a full disk would) leaves the old
// file whole and no temporary file.
TEST(WriteFileAtomicallyTest, FailedWriteKeepsTheOldContent) {
  const std::string folder = FreshTestTempDir("failed_write");
  const std::string path = folder + "/metrics.json";
  WriteFileAtomically(path, "old content\n");

  rlimit before{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &before), 0);
  rlimit small = before;
  small.rlim_cur = 4096;
  const sighandler_t old_handler = signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of a signal
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string error = ErrorOf([&] { WriteFileAtomically(path, std::string(1 << 20, 'n')); });
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &before), 0);
  signal(SIGXFSZ, old_handler);

  EXPECT_THAT(error, AllOf(HasSubstr(path), HasSubstr(std::strerror(EFBIG))));
  EXPECT_EQ(ReadAll(path), "old content\n");
  EXPECT_EQ(Entries(folder), std::vector<std::string>{"metrics.json"});
}

TEST(WriteFileAtomicallyTest, AFolderInTheWayIsNotReplaced) {
  const std::string folder = FreshTestTempDir("folder_in_the_way");
  fs::create_directories(folder + "/map.pgm/inside");
  EXPECT_THAT(ErrorOf([&] { WriteFileAtomically(folder + "/map.pgm", "P5"); }),
              HasSubstr(folder + "/map.pgm"));
  EXPECT_TRUE(fs::is_directory(folder + "/map.pgm/inside"));
  EXPECT_EQ(Entries(folder), std::vector<std::string>{"map.pgm"});
}

}  // namespace
}  // namespace aslam
