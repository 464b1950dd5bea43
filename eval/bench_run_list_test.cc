#include "eval/bench_run_list.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/test_temp_dir.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string ErrorOf(const std::string& path) {
  try {
    ReadRunList(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

RunListEntry Entry(const std::string& dir, int seed) {
  return {dir, "/worlds/office", "ours", seed, 1800.0, "/cfg/aslam.yaml", std::nullopt};
}

TEST(RunListTest, WrittenListReadsBackLineByLine) {
  const std::string path = TestTempDir() + "/run_list.tsv";
  RunListEntry second = Entry("/out/runs/office/ours/seed_02", 2);
  second.config_file = "";
  second.duration_s = 0.1;
  second.start = Pose2d{1.5, -2.25, 3.0};
  WriteRunList(path, {Entry("/out/runs/office/ours/seed_01", 1), second});
  const std::vector<RunListEntry> read = ReadRunList(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].dir, "/out/runs/office/ours/seed_01");
  EXPECT_EQ(read[0].world, "/worlds/office");
  EXPECT_EQ(read[0].method, "ours");
  EXPECT_EQ(read[0].seed, 1);
  EXPECT_EQ(read[0].duration_s, 1800.0);
  EXPECT_EQ(read[0].config_file, "/cfg/aslam.yaml");
  EXPECT_FALSE(read[0].start.has_value());
  EXPECT_EQ(read[1].config_file, "");
  EXPECT_EQ(read[1].duration_s, 0.1);  // every digit kept
  ASSERT_TRUE(read[1].start.has_value());
  EXPECT_EQ(read[1].start->x_m, 1.5);
  EXPECT_EQ(read[1].start->y_m, -2.25);
  EXPECT_EQ(read[1].start->yaw_rad, 3.0);
}

TEST(RunListTest, EntriesCarryAbsolutePathsAndTheBenchOptions) {
  BenchOptions options;
  options.duration_s = 600.0;
  options.start = Pose2d{1.0, 2.0, 0.5};
  const BenchRun run{"worlds/office",    "office", "fd", 3, "out/runs/office/fd/seed_03", "",
                     "config/aslam.yaml"};
  const RunListEntry entry = MakeRunListEntry(options, run);
  EXPECT_EQ(entry.dir, (fs::current_path() / "out/runs/office/fd/seed_03").string());
  EXPECT_EQ(entry.world, (fs::current_path() / "worlds/office").string());
  EXPECT_EQ(entry.config_file, (fs::current_path() / "config/aslam.yaml").string());
  EXPECT_EQ(entry.method, "fd");
  EXPECT_EQ(entry.seed, 3);
  EXPECT_EQ(entry.duration_s, 600.0);
  EXPECT_EQ(ExploreArgv("/bin/aslam", entry),
            (std::vector<std::string>{"/bin/aslam", "explore", "--inproc", "--world", entry.world,
                                      "--method", "fd", "--seed", "3", "--duration", "600", "--out",
                                      entry.dir, "--progress", "60", "--config", entry.config_file,
                                      "--start", "1,2,0.5"}));
  // No config: the built-in defaults, and no --config.
  const RunListEntry plain = MakeRunListEntry(BenchOptions{}, {"w", "w", "fd", 1, "d", "", ""});
  const std::vector<std::string> argv = ExploreArgv("aslam", plain);
  EXPECT_EQ(std::count(argv.begin(), argv.end(), "--config"), 0);
  EXPECT_EQ(std::count(argv.begin(), argv.end(), "--start"), 0);
}

TEST(RunListTest, AFieldWithATabIsRefusedByName) {
  RunListEntry entry = Entry("/out/a\tb", 1);
  try {
    WriteRunList(TestTempDir() + "/run_list.tsv", {entry});
    FAIL() << "a tab in a path was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("the dir '/out/a\tb' holds a tab or a newline"));
  }
}

TEST(RunListTest, MalformedListsNameFileAndLine) {
  const std::string dir = TestTempDir();
  const std::string header = "# comment\ndir\tworld\tmethod\tseed\tduration_s\tconfig\tstart\n";
  const std::string good = "/d\t/w\tfd\t1\t60\t\t\n";
  auto write = [&](const std::string& name, const std::string& text) {
    WriteFile(dir + "/" + name, text);
    return dir + "/" + name;
  };
  EXPECT_THAT(ErrorOf(dir + "/missing.tsv"), HasSubstr("missing.tsv: No such file"));
  EXPECT_THAT(ErrorOf(write("no_header.tsv", good)),
              HasSubstr("no_header.tsv:1: expected the header"));
  EXPECT_THAT(ErrorOf(write("empty.tsv", "")), HasSubstr("empty.tsv: no header line"));
  EXPECT_THAT(ErrorOf(write("fields.tsv", header + good + "/d\t/w\tfd\t1\n")),
              HasSubstr("fields.tsv:4: expected 7 tab-separated fields, got 4"));
  EXPECT_THAT(ErrorOf(write("seed.tsv", header + "/d\t/w\tfd\tone\t60\t\t\n")),
              HasSubstr("seed.tsv:3: seed 'one' is not a whole number"));
  EXPECT_THAT(ErrorOf(write("duration.tsv", header + "/d\t/w\tfd\t1\t-5\t\t\n")),
              HasSubstr("duration.tsv:3: "));
  EXPECT_THAT(ErrorOf(write("method.tsv", header + "/d\t/w\tbest\t1\t60\t\t\n")),
              HasSubstr("method.tsv:3: "));
  EXPECT_THAT(ErrorOf(write("start.tsv", header + "/d\t/w\tfd\t1\t60\t\t1,2\n")),
              HasSubstr("start.tsv:3: start '1,2': expected X,Y,YAW"));
  EXPECT_EQ(ReadRunList(write("good.tsv", header + good)).size(), 1u);
}

// ExecBenchTask returns (no exec) only for a finished run or an error; both leave the run as it
// was. /bin/false stands in for aslam: were it executed, the run's explore.log would say so.
TEST(ExecBenchTaskTest, AFinishedRunIsNotRunAgainAndBadIndicesAreRefused) {
  const std::string dir = TestTempDir();
  const BenchRun finished{"w", "w", "fd", 1, dir + "/runs/w/fd/seed_01", "", ""};
  FakeFinishedRun(finished, {{"coverage", "0.5"}});
  const std::string list = dir + "/run_list.tsv";
  WriteRunList(list, {{finished.dir, "/w", "fd", 1, 60.0, "", std::nullopt}});
  EXPECT_EQ(ExecBenchTask("/bin/false", list, "0"), 0);
  EXPECT_FALSE(fs::exists(finished.dir + "/explore.log"));
  for (const std::string index : {"1", "-1", "x", ""}) {
    EXPECT_EQ(ExecBenchTask("/bin/false", list, index), 1) << index;
  }
  EXPECT_EQ(ExecBenchTask("/bin/false", dir + "/none.tsv", "0"), 1);
}

// The task execs the binary with the run's explore arguments, its output appended to the run's
// explore.log under a header naming the run. A shell script stands in for aslam.
TEST(ExecBenchTaskTest, ExecsExploreWithItsOutputAppendedToTheRunsLog) {
  const std::string dir = TestTempDir();
  const std::string fake = dir + "/fake_aslam";
  WriteFile(fake, "#!/bin/sh\necho \"args: $*\"\necho oops >&2\nexit 3\n");
  fs::permissions(fake, fs::perms::owner_all);
  const std::string run_dir = dir + "/runs/w/ags/seed_02";
  WriteFile(run_dir + "/explore.log", "an earlier attempt\n");
  const std::string list = dir + "/run_list.tsv";
  WriteRunList(list, {Entry(dir + "/other", 1), {run_dir, "/w", "ags", 2, 60, "", std::nullopt}});
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ExecBenchTask(fake, list, "1");
    _exit(99);  // not exec'd
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);  // the binary's own exit status
  const std::string log = ReadFile(run_dir + "/explore.log");
  EXPECT_EQ(log.rfind("an earlier attempt\n=== aslam bench-task: run 1 of " + list + " on ", 0), 0u)
      << log;
  EXPECT_THAT(log, HasSubstr("\nargs: explore --inproc --world /w --method ags --seed 2 "
                             "--duration 60 --out " +
                             run_dir + " --progress 60\noops\n"));
  EXPECT_FALSE(fs::exists(dir + "/other"));
}

}  // namespace
}  // namespace aslam
