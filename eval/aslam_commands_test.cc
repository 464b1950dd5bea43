#include "eval/aslam_commands.h"

#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "common/subprocess.h"
#include "common/test_temp_dir.h"
#include "eval/bench_testing.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

// TakeSetArguments on `argv`: the --set values and the arguments left for gflags.
std::pair<std::vector<std::string>, std::vector<std::string>> Take(std::vector<std::string> argv) {
  std::vector<char*> args;
  for (std::string& arg : argv) args.push_back(arg.data());
  const std::vector<std::string> sets = TakeSetArguments(&args);
  return {sets, std::vector<std::string>(args.begin(), args.end())};
}

TEST(TakeSetArgumentsTest, EveryFormInOrderOthersLeftForGflags) {
  const auto [sets, rest] = Take({"aslam", "--world", "w", "--set", "a.b=1", "--set=c=[1, 2]",
                                  "-set", "d=x", "-set=e=2", "--settings", "--out", "o"});
  EXPECT_EQ(sets, (std::vector<std::string>{"a.b=1", "c=[1, 2]", "d=x", "e=2"}));
  EXPECT_EQ(rest, (std::vector<std::string>{"aslam", "--world", "w", "--settings", "--out", "o"}));
}

TEST(TakeSetArgumentsTest, NoSetChangesNothing) {
  const auto [sets, rest] = Take({"aslam", "--world", "w", "set", "--out=o"});
  EXPECT_TRUE(sets.empty());
  EXPECT_EQ(rest, (std::vector<std::string>{"aslam", "--world", "w", "set", "--out=o"}));
}

TEST(TakeSetArgumentsTest, StopsAtDoubleDashAndNeedsAValue) {
  const auto [sets, rest] = Take({"aslam", "--set", "a=1", "--", "--set", "b=2"});
  EXPECT_EQ(sets, (std::vector<std::string>{"a=1"}));
  EXPECT_EQ(rest, (std::vector<std::string>{"aslam", "--", "--set", "b=2"}));
  EXPECT_THROW(Take({"aslam", "--out", "o", "--set"}), std::invalid_argument);
}

// `aslam explore ARGS` as a child: its exit code and output.
std::pair<int, std::string> Explore(const std::string& name, std::vector<std::string> args) {
  const std::string out = FreshTestTempDir(name);
  SubprocessOptions spawn;
  spawn.argv = {
      ASLAM_BINARY, "explore",    "--world",    std::string(ASLAM_SOURCE_DIR) + "/worlds/test",
      "--method",   "fd",         "--seed",     "3",
      "--out",      out + "/run", "--progress", "0"};
  spawn.argv.insert(spawn.argv.end(), args.begin(), args.end());
  spawn.output_path = out + "/explore.log";
  const int code = Subprocess::Spawn(spawn).Wait().CodeOrMinusSignal();
  return {code, ReadFile(spawn.output_path)};
}

// The loaders reject the misspelt key of a --set, naming it, before anything runs; in both
// modes (process mode fails before starting procman).
TEST(ExploreSetTest, MisspeltKeyFailsNamingIt) {
  for (const std::string mode : {"--inproc", "--rate=0"}) {
    const auto [code, output] = Explore("set_typo", {mode, "--set", "utility.lamda=1"});
    EXPECT_EQ(code, 1) << output;
    EXPECT_THAT(output, AllOf(HasSubstr("run/config.yaml"), HasSubstr("utility.lamda"),
                              HasSubstr("unknown key")));
  }
  const auto [code, output] = Explore("set_bad", {"--inproc", "--set", "utility.lambda"});
  EXPECT_EQ(code, 2) << output;
  EXPECT_THAT(output, HasSubstr("--set 'utility.lambda': expected KEY=VALUE"));
  const auto [method_code, method_output] =
      Explore("set_method", {"--inproc", "--set", "utility.method=ours"});
  EXPECT_EQ(method_code, 2) << method_output;
  EXPECT_THAT(method_output, HasSubstr("--method"));
}

// The run reads the overridden config (a bad value is caught as the config's), and the
// effective one is recorded as OUT/config.yaml; without --set there is none.
TEST(ExploreSetTest, RunReadsAndRecordsTheEffectiveConfig) {
  const auto [bad_code, bad_output] = Explore(
      "set_range", {"--inproc", "--config", std::string(ASLAM_SOURCE_DIR) + "/config/aslam.yaml",
                    "--set", "utility.lambda=-1"});
  EXPECT_EQ(bad_code, 1) << bad_output;
  EXPECT_THAT(bad_output, AllOf(HasSubstr("utility.lambda = '-1'"), HasSubstr("[0, 1000]")));

  const auto [code, output] =
      Explore("set_run", {"--inproc", "--duration", "3", "--set", "utility.lambda=1.2", "--set",
                          "utility.hallucination.loop_closure_scale=2"});
  ASSERT_EQ(code, 0) << output;
  const std::string run = TestTempPath("set_run") + "/run";
  const YAML::Node config = YAML::LoadFile(run + "/config.yaml");
  EXPECT_EQ(config["utility"]["lambda"].as<double>(), 1.2);
  EXPECT_EQ(config["utility"]["hallucination"]["loop_closure_scale"].as<double>(), 2.0);
  EXPECT_EQ(config["utility"]["method"].as<std::string>(), "fd");  // as run: --method
  EXPECT_EQ(config["sim"]["seed"].as<int>(), 3);
  EXPECT_TRUE(fs::exists(run + "/metrics.json"));

  const auto [plain_code, plain_output] = Explore("set_none", {"--inproc", "--duration", "1"});
  ASSERT_EQ(plain_code, 0) << plain_output;
  EXPECT_FALSE(fs::exists(TestTempPath("set_none") + "/run/config.yaml"));
}

// `aslam ARGS` as a child (no defaults added): its exit code and output.
std::pair<int, std::string> Aslam(const std::string& log, std::vector<std::string> args) {
  SubprocessOptions spawn;
  spawn.argv = {ASLAM_BINARY};
  spawn.argv.insert(spawn.argv.end(), args.begin(), args.end());
  spawn.output_path = log;
  const int code = Subprocess::Spawn(spawn).Wait().CodeOrMinusSignal();
  return {code, ReadFile(spawn.output_path)};
}

// A duration that is not a finite number of seconds > 0 fails at once, naming the flag and the
// value, in both modes of explore and in bench, before anything is written.
TEST(DurationFlagTest, InfNanNegativeAndZeroAreRefusedNamingTheValue) {
  const std::vector<std::pair<std::string, std::string>> values = {
      {"inf", "inf"}, {"nan", "nan"}, {"-5", "-5"}, {"0", "0"}, {"-inf", "-inf"}};
  for (const auto& [value, shown] : values) {
    for (const std::string mode : {"--inproc", "--rate=0"}) {
      const std::string name = "duration_" + value + mode.substr(2, 6);
      const auto [code, output] = Explore(name, {mode, "--duration=" + value});
      EXPECT_EQ(code, 2) << value << " " << mode << ": " << output;
      EXPECT_THAT(output, AllOf(HasSubstr("aslam explore: --duration "), HasSubstr(shown),
                                HasSubstr("finite number of simulated seconds > 0")))
          << value << " " << mode;
      EXPECT_FALSE(fs::exists(TestTempPath(name) + "/run"))
          << value << " " << mode << ": the run started";
    }
    const std::string out = FreshTestTempDir("bench_duration_" + value);
    const auto [code, output] =
        Aslam(out + ".log", {"bench", "--worlds", "test", "--methods", "fd", "--seeds", "1",
                             "--duration", value, "--out", out + "/bench"});
    EXPECT_EQ(code, 2) << value << ": " << output;
    EXPECT_THAT(output, AllOf(HasSubstr("aslam bench: --duration "), HasSubstr(shown)));
    EXPECT_FALSE(fs::exists(out + "/bench")) << value << ": the bench started";
  }
  // The flag with its value as the next argument.
  const auto [code, output] = Explore("duration_space", {"--inproc", "--duration", "-5"});
  EXPECT_EQ(code, 2) << output;
  EXPECT_THAT(output, HasSubstr("--duration -5"));
}

// --slurm's options are refused without --slurm or with a bad value, naming the flag, before
// anything is written; a machine without sbatch is told which package has it.
TEST(BenchSlurmFlagsTest, RefusedNamingTheFlagAndAMissingSbatchNamesItsPackage) {
  const std::string out = FreshTestTempDir("slurm_flags");
  const std::vector<std::string> bench = {"bench", "--worlds", "test",        "--methods",
                                          "fd",    "--seeds",  "1",           "--duration",
                                          "10",    "--out",    out + "/bench"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = bench;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  for (const std::string flag : {"--partition=short", "--time=10", "--mem=2G", "--no_wait"}) {
    const auto [code, output] = Aslam(out + "/flag.log", with({flag}));
    EXPECT_EQ(code, 2) << flag << ": " << output;
    EXPECT_THAT(output, HasSubstr("is an option of --slurm, which is not given")) << flag;
  }
  const auto [bad_code, bad_output] = Aslam(out + "/bad.log", with({"--slurm", "--mem=2 G"}));
  EXPECT_EQ(bad_code, 2) << bad_output;
  EXPECT_THAT(bad_output, HasSubstr("--mem '2 G'"));
  EXPECT_FALSE(fs::exists(out + "/bench"));

  SubprocessOptions spawn;
  spawn.argv = {ASLAM_BINARY};
  const std::vector<std::string> args = with({"--slurm"});
  spawn.argv.insert(spawn.argv.end(), args.begin(), args.end());
  spawn.env["PATH"] = out;  // no sbatch, squeue or scontrol here
  spawn.output_path = out + "/no_sbatch.log";
  EXPECT_EQ(Subprocess::Spawn(spawn).Wait().CodeOrMinusSignal(), 1);
  EXPECT_THAT(ReadFile(spawn.output_path),
              AllOf(HasSubstr("cannot run sbatch"), HasSubstr("slurm-client")));
}

// `aslam log-stats` on a recorded log cut short in the middle of an event: the figures of what
// it read, and a warning naming the file and the byte where reading stopped.
TEST(LogStatsCommandTest, TruncatedLogWarnsNamingTheFileAndTheOffset) {
  const std::string out = FreshTestTempDir("log_stats_truncated");
  const std::string log = out + "/run.lcmlog";
  fs::copy_file(std::string(ASLAM_SOURCE_DIR) + "/logs/test_drive.lcmlog", log);
  const auto whole_bytes = fs::file_size(log);
  const auto [whole_code, whole_output] = Aslam(out + "/whole.txt", {"log-stats", log});
  EXPECT_EQ(whole_code, 0) << whole_output;
  EXPECT_THAT(whole_output, HasSubstr("LIDAR_SCAN -> CMD_VEL"));
  EXPECT_THAT(whole_output, ::testing::Not(HasSubstr("warning")));

  fs::resize_file(log, whole_bytes / 2 + 7);  // an event of the fixture is far longer than 7 B
  const auto [code, output] = Aslam(out + "/cut.txt", {"log-stats", log});
  EXPECT_EQ(code, 0) << output;
  EXPECT_THAT(output, AllOf(HasSubstr("LIDAR_SCAN -> CMD_VEL"),
                            HasSubstr("aslam log-stats: warning: " + log + " is truncated"),
                            HasSubstr("stopped at byte "),
                            HasSubstr(" of " + std::to_string(whole_bytes / 2 + 7)),
                            HasSubstr("log: TRUNCATED")));
}

}  // namespace
}  // namespace aslam
