#include "procman/launch_config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

namespace aslam {
namespace {

const LaunchVariables kVars = {{"LCM_URL", "udpm://239.255.76.67:7700?ttl=0"}, {"OUT", "/tmp/run"}};

const char* kGood = R"(
procman:
  deputy: test
  stop_timeout_s: 2
  processes:
    - name: sleeper
      command: /bin/sleep
      args: ["10"]
    - name: sim
      command: aslam-sim
      args: [--lcm-url, "${LCM_URL}", "--out=${OUT}/x"]
      env: {ASLAM_MODE: fast, WHERE: "${OUT}"}
      group: pipeline
      start_order: -1
      auto_start: false
      start_delay_s: 0.5
      restart: on-failure
      backoff: {initial_s: 0.25, max_s: 4, factor: 3, reset_after_s: 5,
                give_up_after_failures: 4}
)";

// The ConfigError message that loading `yaml` throws; "" when it loads.
std::string ErrorOf(const std::string& yaml, const LaunchVariables& vars = kVars) {
  try {
    LoadLaunchConfigFromString(yaml, vars, "launch.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string OneProcess(const std::string& extra_lines) {
  return "procman:\n  processes:\n    - name: p\n      command: /bin/true\n" + extra_lines;
}

TEST(LaunchConfigTest, LoadsEveryField) {
  const LaunchConfig c = LoadLaunchConfigFromString(kGood, kVars);
  EXPECT_EQ(c.deputy, "test");
  EXPECT_EQ(c.stop_timeout_s, 2.0);
  ASSERT_EQ(c.processes.size(), 2u);
  const ProcessConfig& sleeper = c.processes[0];
  EXPECT_EQ(sleeper.name, "sleeper");
  EXPECT_EQ(sleeper.args, std::vector<std::string>{"10"});
  EXPECT_EQ(sleeper.restart, RestartPolicy::kNever);  // the defaults
  EXPECT_TRUE(sleeper.auto_start);
  EXPECT_EQ(sleeper.start_order, 0);
  EXPECT_EQ(sleeper.group, "");
  const ProcessConfig& sim = c.processes[1];
  EXPECT_EQ(sim.command, "aslam-sim");
  EXPECT_EQ(sim.args, (std::vector<std::string>{"--lcm-url", "udpm://239.255.76.67:7700?ttl=0",
                                                "--out=/tmp/run/x"}));
  EXPECT_EQ(sim.env.at("ASLAM_MODE"), "fast");
  EXPECT_EQ(sim.env.at("WHERE"), "/tmp/run");
  EXPECT_EQ(sim.group, "pipeline");
  EXPECT_EQ(sim.start_order, -1);
  EXPECT_FALSE(sim.auto_start);
  EXPECT_EQ(sim.start_delay_s, 0.5);
  EXPECT_EQ(sim.restart, RestartPolicy::kOnFailure);
  EXPECT_EQ(sim.backoff.initial_s, 0.25);
  EXPECT_EQ(sim.backoff.max_s, 4.0);
  EXPECT_EQ(sim.backoff.factor, 3.0);
  EXPECT_EQ(sim.backoff.reset_after_s, 5.0);
  EXPECT_EQ(sim.backoff.give_up_after_failures, 4);
}

TEST(LaunchConfigTest, RestartPolicies) {
  for (const auto& [text, policy] :
       std::vector<std::pair<std::string, RestartPolicy>>{{"never", RestartPolicy::kNever},
                                                          {"on-failure", RestartPolicy::kOnFailure},
                                                          {"always", RestartPolicy::kAlways}}) {
    const LaunchConfig c =
        LoadLaunchConfigFromString(OneProcess("      restart: " + text + "\n"), kVars);
    EXPECT_EQ(c.processes[0].restart, policy) << text;
    EXPECT_EQ(RestartPolicyName(policy), text);
  }
}

TEST(LaunchConfigTest, UnknownRestartPolicyNamesFileLineKeyAndValue) {
  EXPECT_EQ(ErrorOf(OneProcess("      restart: sometimes\n")),
            "launch.yaml:5: procman.processes[0].restart = 'sometimes': unknown restart policy; "
            "expected never, on-failure or always");
}

TEST(LaunchConfigTest, EveryBadKeyOrValueIsNamed) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {OneProcess("      colour: red\n"),
       "launch.yaml:5: procman.processes[0].colour = 'red': unknown key"},
      {OneProcess("      args: --fast\n"),
       "procman.processes[0].args = '--fast': expected a list of strings"},
      {OneProcess("      args: [[1]]\n"),
       "procman.processes[0].args = [[1]]: expected a list of strings"},
      {OneProcess("      args: [\"${NOPE}\"]\n"),
       "procman.processes[0].args = [\"${NOPE}\"]: unknown variable ${NOPE}; known: LCM_URL, OUT"},
      {OneProcess("      args: [\"${OUT\"]\n"), "unterminated ${"},
      {OneProcess("      env: [A]\n"), "procman.processes[0].env = [A]: expected a mapping"},
      {OneProcess("      env: {A: [1]}\n"), "procman.processes[0].env.A = [1]: expected a string"},
      {OneProcess("      group: a/b\n"), "procman.processes[0].group = 'a/b'"},
      {OneProcess("      start_order: first\n"),
       "procman.processes[0].start_order = 'first': expected an integer"},
      {OneProcess("      auto_start: maybe\n"),
       "procman.processes[0].auto_start = 'maybe': expected true or false"},
      {OneProcess("      start_delay_s: -1\n"),
       "procman.processes[0].start_delay_s = '-1': must be in [0, 3600]"},
      {OneProcess("      backoff: {initial_s: -1}\n"),
       "procman.processes[0].backoff.initial_s = '-1': must be in"},
      {OneProcess("      backoff: {factor: 0.5}\n"),
       "procman.processes[0].backoff.factor = '0.5': must be in [1, 100]"},
      {OneProcess("      backoff: {initial_s: 5, max_s: 1}\n"),
       "procman.processes[0].backoff.max_s = '1': must not be below initial_s"},
      {OneProcess("      backoff: {give_up_after_failures: -1}\n"),
       "procman.processes[0].backoff.give_up_after_failures = '-1': must be in"},
      {OneProcess("      backoff: {give_up_after_failures: 2.5}\n"),
       "procman.processes[0].backoff.give_up_after_failures = '2.5': expected an integer"},
      {OneProcess("      backoff: {jitter: 1}\n"),
       "procman.processes[0].backoff.jitter = '1': unknown key"},
      {"procman:\n  processes:\n    - command: /bin/true\n",
       "procman.processes[0].name = null: required"},
      {"procman:\n  processes:\n    - name: ../x\n      command: /bin/true\n",
       "procman.processes[0].name = '../x'"},
      {"procman:\n  processes:\n    - name: p\n", "procman.processes[0].command = null: required"},
      {"procman:\n  processes:\n    - name: p\n      command: a\n    - name: p\n      command: b\n",
       "launch.yaml:5: procman.processes[1].name = 'p': duplicate process name"},
      {"procman:\n  processes: []\n", "procman.processes = []: expected a non-empty list"},
      {"procman:\n  processes: {}\n", "procman.processes = {}: expected a list"},
      {"procman:\n  stop_timeout_s: soon\n  processes: []\n",
       "procman.stop_timeout_s = 'soon': expected a number"},
      {"procman:\n  deputy: a b\n  processes: []\n", "procman.deputy = 'a b'"},
      {"procman:\n  sheriff: x\n  processes: []\n",
       "launch.yaml:2: procman.sheriff = 'x': unknown key"},
      {"launch:\n  processes: []\n", "launch.yaml:1: unknown section 'launch'"},
      {"procman: [\n", "malformed YAML"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string error = ErrorOf(yaml);
    EXPECT_NE(error.find(expected), std::string::npos) << yaml << "\n  gave: " << error;
  }
}

TEST(LaunchConfigTest, MissingFileIsNamed) {
  try {
    LoadLaunchConfigFromFile("/nonexistent/launch.yaml", kVars);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/launch.yaml: cannot open config file");
  }
}

TEST(LaunchConfigTest, Substitution) {
  EXPECT_EQ(SubstituteVariables("a${OUT}b${OUT}", kVars), "a/tmp/runb/tmp/run");
  EXPECT_EQ(SubstituteVariables("no vars $OUT {OUT}", kVars), "no vars $OUT {OUT}");
  EXPECT_THROW(SubstituteVariables("${X}", kVars), std::invalid_argument);
}

TEST(BackoffTest, GrowsByFactorUpToMax) {
  BackoffOptions b;
  b.initial_s = 0.5;
  b.factor = 2.0;
  b.max_s = 3.0;
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 1), 0.5);
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 2), 1.0);
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 3), 2.0);
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 4), 3.0);
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 100000), 3.0);  // no overflow on a long streak
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 0), 0.5);
  b.factor = 1.0;
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 50), 0.5);
  b.initial_s = 0.0;
  EXPECT_DOUBLE_EQ(BackoffDelayS(b, 5), 0.0);
}

// Every shipped launch config loads, given the variables its header names.
TEST(LaunchConfigTest, ShippedLaunchConfigsLoad) {
  const LaunchVariables vars = {{"LCM_URL", "udpm://239.255.76.67:7700?ttl=0"},
                                {"LOG_DIR", "/tmp/run"},
                                {"OUT", "/tmp/run"},
                                {"BUILD", "/build"},
                                {"SRC", ASLAM_SOURCE_DIR},
                                {"WORLD", "worlds/test"},
                                {"CONFIG", "config/aslam.yaml"},
                                {"DURATION", "60"},
                                {"SEED", "1"},
                                {"RATE", "1"}};
  int loaded = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(ASLAM_SOURCE_DIR) + "/config/launch")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const LaunchConfig c = LoadLaunchConfigFromFile(entry.path().string(), vars);
    EXPECT_FALSE(c.processes.empty());
    ++loaded;
  }
  EXPECT_GE(loaded, 1);
}

TEST(LaunchConfigTest, ExploreTemplateRecordsTheBusAndStartsTheSimLast) {
  const LaunchVariables vars = {
      {"LCM_URL", "udpm://u"}, {"LOG_DIR", "/o"}, {"OUT", "/o"},        {"BUILD", "/b"},
      {"SRC", "/s"},           {"WORLD", "w"},    {"CONFIG", "c.yaml"}, {"DURATION", "60"},
      {"SEED", "7"},           {"RATE", "2"}};
  const LaunchConfig c =
      LoadLaunchConfigFromFile(std::string(ASLAM_SOURCE_DIR) + "/config/launch/explore.yaml", vars);
  std::map<std::string, const ProcessConfig*> by_name;
  for (const auto& p : c.processes) by_name[p.name] = &p;
  for (const char* name : {"lcm-logger", "sim", "slam", "frontier", "utility", "nav"}) {
    ASSERT_TRUE(by_name.count(name)) << name;
  }
  EXPECT_EQ(by_name["lcm-logger"]->args.back(), "/o/run.lcmlog");
  EXPECT_EQ(by_name["sim"]->command, "/b/drivers/sim/aslam-sim");
  EXPECT_EQ(by_name["sim"]->restart, RestartPolicy::kNever);
  for (const auto& p : c.processes) {
    EXPECT_LE(by_name["lcm-logger"]->start_order, p.start_order);
    EXPECT_GE(by_name["sim"]->start_order, p.start_order);
  }
}

// Whether `flag` is followed by `value` among the process's arguments.
bool HasFlag(const ProcessConfig& p, const std::string& flag, const std::string& value) {
  for (std::size_t i = 0; i + 1 < p.args.size(); ++i) {
    if (p.args[i] == flag && p.args[i + 1] == value) return true;
  }
  return false;
}

// The robot's launch files (the deputy that aslam-deputy.service starts at boot): the drivers
// start with the deputy and stop last, the recorder and the exploration wait for a sheriff's
// `start`, every process is on the deputy's bus and reads the config given as CONFIG.
TEST(LaunchConfigTest, RobotLaunchFilesStartTheDriversAndLeaveThePipelineToTheUser) {
  const std::string url = "udpm://239.255.76.67:7667?ttl=1";
  const LaunchVariables vars = {{"LCM_URL", url},   {"LOG_DIR", "/runs/1"},
                                {"OUT", "/runs/1"}, {"BUILD", "/opt/aslam/build"},
                                {"SRC", "/src"},    {"CONFIG", "/etc/aslam/aslam.yaml"}};
  for (const std::string lidar : {"rplidar", "hokuyo"}) {
    const std::string file =
        std::string(ASLAM_SOURCE_DIR) + "/config/launch/robot_" + lidar + "_kobuki.yaml";
    SCOPED_TRACE(file);
    const LaunchConfig c = LoadLaunchConfigFromFile(file, vars);
    EXPECT_EQ(c.deputy, "robot");
    std::map<std::string, const ProcessConfig*> by_name;
    for (const auto& p : c.processes) by_name[p.name] = &p;
    const std::map<std::string, std::string> groups = {
        {"kobuki", "drivers"}, {lidar, "drivers"},       {"lcm-logger", "record"},
        {"slam", "pipeline"},  {"frontier", "pipeline"}, {"utility", "pipeline"},
        {"nav", "pipeline"}};
    ASSERT_EQ(by_name.size(), groups.size());
    for (const auto& [name, group] : groups) {
      ASSERT_TRUE(by_name.count(name)) << name;
      const ProcessConfig& p = *by_name.at(name);
      EXPECT_EQ(p.group, group) << name;
      EXPECT_EQ(p.auto_start, group == "drivers") << name;
      EXPECT_NE(p.restart, RestartPolicy::kNever) << name;
      EXPECT_TRUE(HasFlag(p, "--lcm-url", url) ||
                  std::find(p.args.begin(), p.args.end(), "--lcm-url=" + url) != p.args.end())
          << name;
      if (name != "lcm-logger") {
        EXPECT_TRUE(HasFlag(p, "--config", "/etc/aslam/aslam.yaml")) << name;
      }
      for (const auto& other : c.processes) {
        // Lower starts first and stops last: drivers, then the recorder, then the pipeline.
        if ((group == "drivers" && other.group != "drivers") ||
            (group == "record" && other.group == "pipeline")) {
          EXPECT_LT(p.start_order, other.start_order) << name << " before " << other.name;
        }
      }
    }
    const ProcessConfig& kobuki = *by_name.at("kobuki");
    EXPECT_EQ(kobuki.command, "/opt/aslam/build/drivers/kobuki/aslam-kobuki");
    EXPECT_TRUE(HasFlag(kobuki, "--port", "/dev/kobuki"));
    const ProcessConfig& sensor = *by_name.at(lidar);
    EXPECT_EQ(sensor.command, "/opt/aslam/build/drivers/" + lidar + "/aslam-" + lidar);
    EXPECT_TRUE(HasFlag(sensor, "--port", "/dev/" + lidar));
    // The log goes into the run folder; a restart appends to it, never overwrites it.
    const ProcessConfig& logger = *by_name.at("lcm-logger");
    EXPECT_EQ(logger.args.back(), "/runs/1/run.lcmlog");
    EXPECT_NE(std::find(logger.args.begin(), logger.args.end(), "--append"), logger.args.end());
    EXPECT_EQ(std::find(logger.args.begin(), logger.args.end(), "--force"), logger.args.end());
    EXPECT_TRUE(HasFlag(*by_name.at("slam"), "--journal-dir", "/runs/1"));
  }
}

}  // namespace
}  // namespace aslam
