#include "eval/explore_process.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "aslam/explore_goal_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/procman_status_t.hpp"
#include "aslam/sim_status_t.hpp"
#include "common/atomic_file.h"
#include "common/channels.h"
#include "common/lcm_util.h"
#include "common/subprocess.h"
#include "common/types_lcm.h"
#include "common/world_file.h"
#include "drivers/sim/sim_config.h"
#include "eval/run_listener.h"
#include "eval/run_outputs.h"
#include "eval/trajectory_metrics.h"
#include "frontier/frontier_config.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_config.h"
#include "procman/process_history.h"
#include "procman/procman_lcm.h"
#include "slam/slam_config.h"
#include "utility/utility_config.h"

#ifndef ASLAM_SOURCE_DIR
#define ASLAM_SOURCE_DIR "."
#endif

namespace aslam {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string Number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::string Absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

// The config the nodes read: the given one (or none) with utility.method set.
std::string WriteNodeConfig(const std::string& config_file, const std::string& method,
                            const std::string& out_dir) {
  YAML::Node root =
      config_file.empty() ? YAML::Node(YAML::NodeType::Map) : YAML::LoadFile(config_file);
  if (!root.IsMap()) root = YAML::Node(YAML::NodeType::Map);
  root["utility"]["method"] = method;
  const std::string path = out_dir + "/config.yaml";
  std::ostringstream text;
  text << "# written by aslam explore from "
       << (config_file.empty() ? "built-in defaults" : config_file) << ", utility.method set to "
       << method << "\n"
       << root << "\n";
  WriteFileAtomically(path, text.str());
  return path;
}

// A --start other than the world's: OUT/world.yaml, the world's (or a bare
// map's) with that start and the map by absolute path. The launch config
// passes no --start (procman's --vars is comma-separated, a pose is X,Y,YAW).
std::string WriteWorldWithStart(const WorldInfo& world, const Pose2d& start,
                                const std::string& out_dir) {
  YAML::Node root = world.world_yaml_path.empty() ? YAML::Node(YAML::NodeType::Map)
                                                  : YAML::LoadFile(world.world_yaml_path);
  if (world.world_yaml_path.empty()) root["name"] = fs::path(world.map_yaml_path).stem().string();
  root["map"] = Absolute(world.map_yaml_path);
  YAML::Node pose(YAML::NodeType::Map);
  pose["x_m"] = start.x_m;
  pose["y_m"] = start.y_m;
  pose["yaw_rad"] = start.yaw_rad;
  pose.SetStyle(YAML::EmitterStyle::Flow);
  root["start"] = pose;
  const std::string path = out_dir + "/world.yaml";
  std::ostringstream text;
  text << "# written by aslam explore: "
       << (world.world_yaml_path.empty() ? world.map_yaml_path : world.world_yaml_path)
       << " with its --start\n"
       << root << "\n";
  WriteFileAtomically(path, text.str());
  (void)LoadWorld(path);
  return path;
}

}  // namespace

std::string PrivateLcmUrl(int pid) {
  // SLAM_MAP spans many datagrams: ask for a 4 MiB receive buffer (the kernel caps it at
  // net.core.rmem_max).
  return "udpm://239.255.76.67:" + std::to_string(17000 + (pid % 10000)) +
         "?ttl=0&recv_buf_size=4194304";
}

bool MulticastRouteExists(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0) return true;
  const std::string rest = url.substr(scheme.size(), url.find('?') - scheme.size());
  const std::size_t colon = rest.rfind(':');
  sockaddr_in group{};
  group.sin_family = AF_INET;
  group.sin_port = htons(colon == std::string::npos
                             ? 7667
                             : static_cast<uint16_t>(std::atoi(rest.c_str() + colon + 1)));
  if (inet_pton(AF_INET, rest.substr(0, colon).c_str(), &group.sin_addr) != 1) return true;
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return true;  // not a routing question: OpenLcm will say what is wrong
  const bool routed = connect(fd, reinterpret_cast<const sockaddr*>(&group), sizeof group) == 0;
  close(fd);
  return routed;
}

std::string WhyNoPrivateNetworkNamespace() {
  SubprocessOptions probe;
  probe.argv = {"unshare", "-rn", "true"};
  probe.output_path = "/dev/null";
  try {
    if (!Subprocess::Spawn(probe).Wait().success()) {
      return "unshare -rn is not permitted here (unprivileged user namespaces are off)";
    }
  } catch (const SpawnError& e) {
    return e.what();
  }
  return "";
}

std::string ExecInPrivateNetworkNamespace(const std::vector<std::string>& argv) {
  std::error_code error;
  const std::string self = fs::read_symlink("/proc/self/exe", error).string();
  if (error) return "cannot find this program (/proc/self/exe): " + error.message();
  const std::string script = std::string(ASLAM_SOURCE_DIR) + "/scripts/in-private-netns";
  std::vector<std::string> args = {script, self};
  args.insert(args.end(), argv.begin() + (argv.empty() ? 0 : 1), argv.end());
  std::vector<char*> pointers;
  for (std::string& arg : args) pointers.push_back(arg.data());
  pointers.push_back(nullptr);
  setenv(kPrivateNetnsVariable, "1", 1);
  std::fflush(stdout);
  execv(script.c_str(), pointers.data());
  const int exec_errno = errno;
  unsetenv(kPrivateNetnsVariable);
  return "cannot run " + script + ": " + std::strerror(exec_errno);
}

std::string AddModeToMetricsJson(const std::string& json, const std::string& mode) {
  const std::size_t end = json.rfind("\n}");
  if (end == std::string::npos) return json;
  return json.substr(0, end) + ",\n  \"mode\": \"" + mode + "\"" + json.substr(end);
}

ExploreResult RunExploreProcess(const ExploreProcessOptions& options, const std::atomic<bool>* stop,
                                const std::function<void(const ExploreProgress&)>& on_progress) {
  const ExploreOptions& ex = options.explore;
  const ExploreMethod method = ParseExploreMethod(ex.method, "--method");
  if (method.ideal) {
    throw std::invalid_argument(
        "--method ideal runs in one process only (--inproc): it maps with SIM_TRUTH, which no "
        "process of the stack may read");
  }
  CheckDuration(ex.duration_s);
  if (!(options.rate >= 0)) throw std::invalid_argument("--rate must be >= 0");
  if (options.out_dir.empty()) throw std::invalid_argument("--out is required");

  // Every option is validated here, before any process starts (docs/architecture.md §7).
  (void)LoadSimulatorOptionsFromFile(ex.config_file);
  (void)LoadSlamConfigFromFile(ex.config_file);
  (void)LoadFrontierOptionsFromFile(ex.config_file);
  (void)LoadUtilityOptionsFromFile(ex.config_file);
  (void)LoadNavOptionsFromFile(ex.config_file);
  const WorldInfo world = LoadWorld(ex.world);
  const Pose2d start = ResolveStart(world, ex);

  const std::string out = Absolute(options.out_dir);
  std::error_code error;
  fs::create_directories(out, error);
  if (error) throw std::runtime_error("cannot create " + out + ": " + error.message());
  const std::string node_config =
      WriteNodeConfig(ex.config_file, UtilityMethodName(method.utility), out);
  (void)LoadUtilityOptionsFromFile(node_config);

  std::string build = options.build_dir;
  if (build.empty()) {
    const fs::path self = fs::read_symlink("/proc/self/exe", error);
    build = error ? "." : self.parent_path().parent_path().string();
  }
  build = Absolute(build);
  const std::string procman = build + "/procman/aslam-procman";
  const std::string launch = !options.launch_file.empty()
                                 ? options.launch_file
                                 : std::string(ASLAM_SOURCE_DIR) + "/config/launch/" +
                                       (options.devices ? "explore_devices.yaml" : "explore.yaml");
  if (options.devices && options.rate != 1.0) {
    throw std::invalid_argument("--devices runs at real time: --rate must be 1, not " +
                                Number(options.rate));
  }
  if (!fs::is_regular_file(launch)) {
    throw std::invalid_argument("--launch '" + launch + "': no such launch config file");
  }
  const std::string url = options.lcm_url.empty() ? PrivateLcmUrl(getpid()) : options.lcm_url;

  const std::vector<std::pair<std::string, std::string>> vars = {
      {"WORLD", ex.start ? WriteWorldWithStart(world, start, out) : Absolute(ex.world)},
      {"CONFIG", node_config},
      {"METHOD", UtilityMethodName(method.utility)},
      {"DURATION", Number(ex.duration_s)},
      {"SEED", std::to_string(ex.seed)},
      {"RATE", Number(options.rate)},
      {"BUILD", build},
  };
  std::string vars_text;
  for (const auto& [key, value] : vars) {
    if (value.find(',') != std::string::npos) {
      throw std::invalid_argument(key + " '" + value + "': procman --vars cannot hold a comma");
    }
    vars_text += (vars_text.empty() ? "" : ",") + key + "=" + value;
  }

  // Listen first, so nothing the simulator says is missed.
  const auto lcm = OpenLcm(url);
  RunListener listener(*lcm, world.map.grid, options.devices);
  // What procman says of its processes: restarts, and one that will not come back.
  ProcessHistoryTracker processes;
  Subscriptions procman_status(*lcm);
  procman_status.Add<procman_status_t>(channels::kProcmanStatus,
                                       [&](const procman_status_t& message) {
                                         DeputyStatus status;
                                         if (!FromLcm(message, &status)) return false;
                                         processes.Add(status);
                                         return true;
                                       });
  // The simulator ends at the duration, and with it the deputy: the run's normal end.
  const std::string exit_when = "sim";

  const Clock::time_point wall_start = Clock::now();
  SubprocessOptions spawn;
  spawn.argv = {procman,     "deputy", "--config", launch,    "--log-dir",   out,
                "--lcm-url", url,      "--vars",   vars_text, "--exit-when", exit_when};
  spawn.output_path = out + "/procman.log";
  // Its own group: a terminal's Ctrl-C reaches only this runner, which stops the deputy in
  // order; SIGTERM to it should this runner die first.
  spawn.own_process_group = true;
  spawn.parent_death_signal = SIGTERM;
  Subprocess deputy = Subprocess::Spawn(spawn);

  ExploreResult result;
  const int64_t end_us = std::llround(ex.duration_s * 1e6);
  const int64_t progress_us = std::llround(ex.progress_period_s * 1e6);
  int64_t next_sample_us = 1'000'000;
  int64_t next_progress_us = progress_us;
  bool interrupted = false;
  bool deputy_ended = false;
  std::string failure;
  std::optional<std::string> lost_process;  // why the run cannot go on as asked

  auto progress = [&] {
    ExploreProgress p = listener.Progress(listener.sim_utime() * 1e-6, Since(wall_start));
    p.restarts = RestartsSummary(processes.processes());
    return p;
  };

  while (true) {
    lcm->handleTimeout(20);
    const int64_t now_us = listener.sim_utime();
    while (listener.heard_sim() && now_us >= next_sample_us) {
      result.coverage.push_back({next_sample_us * 1e-6, listener.coverage()});
      result.uncertainty.push_back({next_sample_us * 1e-6, listener.mean_edge_d_opt()});
      next_sample_us += 1'000'000;
    }
    if (on_progress && progress_us > 0 && now_us >= next_progress_us) {
      on_progress(progress());
      while (next_progress_us <= now_us) next_progress_us += progress_us;
    }
    if (listener.done() || listener.stopped() || now_us >= end_us) break;
    if (stop && stop->load()) {
      interrupted = true;
      break;
    }
    lost_process = LostProcess(processes.processes(), exit_when);
    if (lost_process) break;
    if (deputy.Poll() || !deputy.running()) {
      deputy_ended = true;
      break;
    }
    if (!listener.heard_sim() && Since(wall_start) > options.startup_timeout_s) {
      failure = "nothing heard from the simulator on " + url + " within " +
                Number(options.startup_timeout_s) + " s: see " + out + "/procman.log and " + out +
                "/sim.log";
      break;
    }
  }

  // Stop the deputy (it stops its processes, lcm-logger last), still listening meanwhile.
  const ExitStatus deputy_status =
      deputy.Terminate(options.stop_timeout_s, [&] { lcm->handleTimeout(20); });
  if (deputy.killed_after_grace()) {
    std::fprintf(stderr, "aslam explore: procman did not stop within %.0f s, killed\n",
                 options.stop_timeout_s);
  }
  while (lcm->handleTimeout(0) > 0) {
  }
  const double wall_s = Since(wall_start);
  if (!failure.empty()) throw std::runtime_error(failure);
  // The deputy ended by itself: a process it gave up on may be why (its status came first).
  if (deputy_ended && !lost_process) lost_process = LostProcess(processes.processes(), exit_when);
  const std::string restarts = RestartsSummary(processes.processes());
  if (!deputy_status.success()) {
    const std::string why =
        restarts.empty() ? "" : ": processes failed (restarts: " + restarts + ")";
    std::fprintf(stderr, "aslam explore: aslam-procman %s %d%s; see %s/procman.log\n",
                 deputy_status.exited() ? "exited with" : "killed by signal",
                 deputy_status.exited() ? deputy_status.code : deputy_status.signal, why.c_str(),
                 out.c_str());
  }
  if (lost_process) {
    std::fprintf(stderr, "aslam explore: the run stopped at %.1f s simulated: %s (see %s/*.log)\n",
                 listener.sim_utime() * 1e-6, lost_process->c_str(), out.c_str());
  }

  if (listener.map()) result.map = *listener.map();
  result.graph = listener.graph();
  const double sim_s = listener.sim_utime() * 1e-6;
  FinishResult(listener, world, ex, UtilityMethodName(method.utility), sim_s, wall_s, &result);
  RunMetrics& m = result.metrics;
  m.collisions = listener.collisions();
  if (const auto& s = listener.status()) {
    m.goals_reached = s->goals_reached;
    m.goals_failed = s->goals_failed;
    m.decisions = s->decisions;
  }
  m.processes = processes.processes();
  m.end_reason = lost_process                                    ? "process-failed"
                 : m.done                                        ? "done"
                 : listener.stopped()                            ? "stopped"
                 : interrupted                                   ? "interrupted"
                 : sim_s >= ex.duration_s - 1.0 || !deputy_ended ? "duration"
                                                                 : "procman-exited";
  if (on_progress) {
    ExploreProgress last = listener.FinalProgress(m, sim_s, wall_s);
    last.restarts = restarts;
    on_progress(last);
  }
  return result;
}

}  // namespace aslam
