#include "procman/procman_commands.h"

#include <sys/prctl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gflags/gflags.h>

#include "common/flags.h"
#include "common/lcm_util.h"
#include "procman/deputy.h"
#include "procman/launch_config.h"
#include "procman/procman_node.h"

DEFINE_string(lcm_url, "", "LCM URL (default: $LCM_DEFAULT_URL, else udpm with ttl=0)");
DEFINE_string(config, "", "deputy: launch config, a YAML file with a `procman:` section");
DEFINE_string(log_dir, "",
              "deputy: folder for NAME.log of each process (default: /tmp/aslam-procman-PID)");
DEFINE_string(vars, "",
              "deputy: KEY=VALUE,... for ${KEY} in the launch config (besides LCM_URL, "
              "LOG_DIR, OUT (= LOG_DIR unless given), BUILD and SRC)");
DEFINE_string(exit_when, "", "deputy: shut down when this process has ended for good");
DEFINE_double(stop_timeout_s, -1, "deputy: TERM-to-KILL timeout; overrides the config's when >= 0");
DEFINE_double(wait_s, 6.0,
              "sheriff: seconds to wait for a deputy and for orders to be carried out");

namespace aslam {
namespace {

std::atomic<bool> g_stop{false};

LaunchVariables Variables(const std::string& url, const std::string& log_dir) {
  LaunchVariables vars;
  vars["LCM_URL"] = url;
  vars["LOG_DIR"] = log_dir;
  vars["OUT"] = log_dir;
  // This binary is BUILD/procman/aslam-procman.
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  vars["BUILD"] = error ? "." : self.parent_path().parent_path().string();
  vars["SRC"] = ASLAM_SOURCE_DIR;
  std::string rest = FLAGS_vars;
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw std::invalid_argument("--vars: expected KEY=VALUE, got '" + item + "'");
    }
    vars[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return vars;
}

int RunDeputy() {
  if (FLAGS_config.empty()) throw std::invalid_argument("deputy: --config LAUNCH.yaml is required");
  const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
  const std::string log_dir =
      std::filesystem::absolute(
          FLAGS_log_dir.empty() ? "/tmp/aslam-procman-" + std::to_string(getpid()) : FLAGS_log_dir)
          .lexically_normal()
          .string();
  LaunchConfig config = LoadLaunchConfigFromFile(FLAGS_config, Variables(url, log_dir));
  if (FLAGS_stop_timeout_s >= 0) config.stop_timeout_s = FLAGS_stop_timeout_s;
  const auto lcm = OpenLcm(url);
  const SteadyClock clock;
  // Orphaned grandchildren come to the deputy, which reaps them: none lingers as a zombie.
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  Deputy deputy(config, DeputyOptions{log_dir, FLAGS_exit_when, true}, clock);
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::printf("aslam-procman: deputy %s on %s, %zu processes, logs in %s\n", config.deputy.c_str(),
              url.c_str(), config.processes.size(), log_dir.c_str());
  std::fflush(stdout);
  return RunDeputyNode(*lcm, deputy, g_stop);
}

int RunVerb(int argc, char** argv) {
  const char* usage =
      "aslam-procman deputy --config LAUNCH.yaml [--lcm-url URL] [--log-dir DIR] "
      "[--exit-when NAME] | start|stop|restart NAME_OR_GROUP | status";
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s\n", usage);
    return 1;
  }
  const std::string verb = argv[1];
  try {
    if (verb == "deputy" && argc == 2) return RunDeputy();
    SheriffOptions options;
    options.wait_s = FLAGS_wait_s;
    if (verb == "status" && argc == 2) {
      const auto lcm = OpenLcm(ResolveLcmUrl(FLAGS_lcm_url));
      return RunSheriffStatus(*lcm, options);
    }
    SheriffCommand command;
    if (ParseSheriffCommand(verb, &command) && argc == 3) {
      const auto lcm = OpenLcm(ResolveLcmUrl(FLAGS_lcm_url));
      return RunSheriffCommand(*lcm, command, argv[2], options);
    }
    std::fprintf(stderr, "usage: %s\n", usage);
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam-procman: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int RunProcmanCommand(int argc, char** argv) {
  ParseFlags(&argc, &argv,
             "aslam-procman deputy --config LAUNCH.yaml [--lcm-url URL] [--log-dir DIR] "
             "[--vars K=V,...] [--exit-when NAME]\n"
             "  | start|stop|restart NAME_OR_GROUP [--lcm-url URL]\n"
             "  | status [--lcm-url URL]");
  return RunVerb(argc, argv);
}

}  // namespace aslam
