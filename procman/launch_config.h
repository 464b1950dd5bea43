#pragma once

// The launch config of aslam-procman: which processes a deputy runs, how, and
// what it does when one ends. Read from the `procman:` section of a YAML file
// and validated once at load time; errors name file, line, key and value.
//
//   procman:
//     deputy: explore              # name the sheriff addresses (default "deputy")
//     stop_timeout_s: 3            # TERM, then KILL after this long
//     processes:
//       - name: sim                # unique; also the log file name (LOG_DIR/sim.log)
//         command: ${BUILD}/drivers/sim/aslam-sim   # PATH is searched for a bare name
//         args: [--lcm-url, "${LCM_URL}"]
//         env: {LCM_DEFAULT_URL: "${LCM_URL}"}  # added to the deputy's environment
//         group: sim               # sheriff commands take a name or a group
//         start_order: 0           # lower starts first, stops last
//         auto_start: true         # started when the deputy starts
//         start_delay_s: 0         # ... this long after the deputy starts
//         restart: on-failure      # never | on-failure | always
//         backoff: {initial_s: 0.5, max_s: 10, factor: 2, reset_after_s: 10,
//                   give_up_after_failures: 0}   # 0 = restart for ever
//
// `${NAME}` in command, args and env values is replaced from the variables the
// caller passes (e.g. LCM_URL, LOG_DIR, BUILD, SRC, OUT); an unknown one is an error.

#include <map>
#include <string>
#include <vector>

#include "common/config.h"

namespace aslam {

enum class RestartPolicy { kNever, kOnFailure, kAlways };

const char* RestartPolicyName(RestartPolicy policy);

struct BackoffOptions {
  double initial_s = 0.5;
  double max_s = 10.0;
  double factor = 2.0;
  // A run at least this long counts as healthy: the next failure backs off from initial_s.
  double reset_after_s = 10.0;
  // After this many failures in a row the process is left failed rather than restarted
  // (a process that cannot come back should say so, not retry unseen); 0 = never give up.
  int give_up_after_failures = 0;
};

// Delay before restart number `consecutive_failures` (1 = the first after a healthy run):
// initial_s * factor^(consecutive_failures - 1), capped at max_s.
double BackoffDelayS(const BackoffOptions& backoff, int consecutive_failures);

struct ProcessConfig {
  std::string name;
  std::string command;
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  std::string group;
  int start_order = 0;
  bool auto_start = true;
  double start_delay_s = 0.0;  // after the deputy starts (auto_start only)
  RestartPolicy restart = RestartPolicy::kNever;
  BackoffOptions backoff;
};

struct LaunchConfig {
  std::string deputy = "deputy";
  double stop_timeout_s = 3.0;
  std::vector<ProcessConfig> processes;  // in file order
};

using LaunchVariables = std::map<std::string, std::string>;

// Replaces every ${NAME} in `text`; throws std::invalid_argument naming an unknown or
// unterminated variable.
std::string SubstituteVariables(const std::string& text, const LaunchVariables& variables);

// Reads and validates the `procman` section of `file`; throws ConfigError.
LaunchConfig LoadLaunchConfigFromFile(const std::string& file, const LaunchVariables& variables);
// The same for YAML text; `origin` names it in errors.
LaunchConfig LoadLaunchConfigFromString(const std::string& yaml_text,
                                        const LaunchVariables& variables,
                                        const std::string& origin = "<string>");

}  // namespace aslam
