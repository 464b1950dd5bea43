#include "eval/aslam_commands.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gflags/gflags.h>

#include "common/atomic_file.h"
#include "common/config.h"
#include "common/flags.h"
#include "common/lcm_util.h"
#include "common/pose2d.h"
#include "common/text_format.h"
#include "eval/bench.h"
#include "eval/bench_run_list.h"
#include "eval/bench_slurm.h"
#include "eval/explore_process.h"
#include "eval/explore_runner.h"
#include "eval/log_stats.h"
#include "eval/run_outputs.h"
#include "utility/explore_control_client.h"
#include "viewer/viewer_app.h"

DEFINE_string(world, "", "world folder (map.yaml + world.yaml) or a map_server MAP.yaml");
DEFINE_string(start, "", "start pose X,Y,YAW in the world frame (m, m, rad); default: the world's");
DEFINE_string(method, "ours",
              "goal selection: fd | ags | ours, or ideal (the ideal explorer: true pose, "
              "nearest frontier; --inproc only)");
DEFINE_double(duration, 1800.0,
              "simulated seconds at most (the run also ends when exploration is done)");
DEFINE_int64(seed, 1, "simulator seed: the same seed gives the same run");
DEFINE_bool(inproc, false, "every node in this process on memq://, as fast as the CPU allows");
DEFINE_double(rate, 1.0,
              "real-time factor of process mode (--inproc always runs as fast as it can)");
DEFINE_string(config, "", "config file (config/aslam.yaml layout); default: built-in defaults");
DEFINE_string(out, "", "run folder to write (created)");
DEFINE_string(lcm_url, "",
              "process mode: LCM URL of the run (default: "
              "udpm://239.255.76.67:PORT?ttl=0&recv_buf_size=4194304, PORT from the pid); "
              "control: the bus of the run to control (default: $LCM_DEFAULT_URL, else udpm "
              "with ttl=0)");
DEFINE_string(launch, "",
              "process mode: aslam-procman launch config (default: config/launch/explore.yaml "
              "of the source tree)");
DEFINE_bool(devices, false,
            "explore, process mode: devices in the loop: aslam-kobuki and aslam-rplidar drive "
            "emulated devices on pseudo-terminals (aslam-sim --devices), at real time "
            "(default launch config: config/launch/explore_devices.yaml)");
DEFINE_double(progress, 10.0, "a progress line every this many simulated seconds; 0 = none");
DEFINE_string(worlds, "office,campus",
              "bench: comma-separated worlds (names under worlds/, folders or MAP.yaml files)");
DEFINE_string(methods, "fd,ags,ours,ideal",
              "bench: comma-separated methods (ideal: the reference row, ideal.md)");
DEFINE_int32(seeds, 15, "bench: seeds 1..N per world and method");
DEFINE_int32(jobs, 0, "bench: runs in parallel (0 = the number of cores)");
DEFINE_bool(plots, true, "bench: draw the figures (python3-matplotlib)");
DEFINE_bool(report_only, false,
            "bench: run nothing; write the tables and figures of the runs already finished");
DEFINE_bool(slurm, false,
            "bench: run on a Slurm cluster, one array job task per run (OUT on a filesystem every "
            "node shares, this aslam at the same path on every node)");
DEFINE_string(partition, "", "bench --slurm: sbatch --partition (default: the cluster's)");
DEFINE_string(time, "",
              "bench --slurm: sbatch --time per run, e.g. 20:00 (default: the partition's)");
DEFINE_string(mem, "", "bench --slurm: sbatch --mem per run, e.g. 2G (default: the partition's)");
DEFINE_string(
    sbatch_args, "",
    "bench --slurm: more sbatch options, space-separated, e.g. '--account=lab --qos=low'");
DEFINE_bool(no_wait, false,
            "bench --slurm: submit and return; rerun the same command to wait and write the "
            "reports");
DEFINE_double(slurm_poll_s, 30.0, "bench --slurm: seconds between squeue calls while waiting");
DEFINE_bool(return_home, false,
            "explore: when exploration is done, drive back to the start, then end "
            "(utility.return_home)");
DEFINE_double(wait, 3.0, "control: seconds to wait for the utility's answer");
DEFINE_int32(port, 8080, "view: the viewer's HTTP port");
DEFINE_string(bind, "127.0.0.1", "view: the address to serve on");

namespace aslam {
namespace {

constexpr const char* kUsage =
    "aslam explore --world DIR|MAP.yaml [--start X,Y,YAW] --method fd|ags|ours|ideal --duration "
    "SEC\n"
    "              --seed N [--inproc] [--rate R] [--lcm-url URL] [--launch FILE] [--config FILE]\n"
    "              [--return-home] [--devices] [--set KEY=VALUE ...] --out DIR\n"
    "aslam bench --worlds W1,W2 --methods fd,ags,ours,ideal --seeds N --duration SEC [--jobs J]\n"
    "            [--start X,Y,YAW] [--config FILE] [--set KEY=V1,V2 ...] [--noplots]\n"
    "            [--report_only] --out DIR\n"
    "aslam bench ... --slurm [--partition P] [--time T] [--mem M] [--sbatch_args '...'] "
    "[--no_wait]\n"
    "aslam bench-task RUN_LIST N   (one run of a bench's run list: what bench's runs execute)\n"
    "aslam log-stats RUN/run.lcmlog\n"
    "aslam control pause|resume|stop|return_home [--lcm-url URL] [--wait SEC]\n"
    "aslam view RUN_FOLDER [--port N] [--bind ADDR]\n"
    "--set KEY=VALUE overrides one config key, e.g. --set utility.lambda=1.2 (repeatable; VALUE\n"
    "is YAML: a scalar or [a, list]); explore records the result as OUT/config.yaml. bench\n"
    "sweeps the grid of every --set's values: OUT/runs/<setting>/..., e.g. the setting\n"
    "utility.lambda=0.3+nav.goal_snap_m=0.1; tables per setting and sweep.md.";

std::atomic<bool> g_stop{false};
// The command line as given, to run it again in a private network namespace.
std::vector<std::string> g_command_line;

void OnSignal(int) {
  g_stop = true;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends at once
}

// --duration checked before anything runs; false after printing why it is refused.
bool CheckDurationFlag(const char* command) {
  try {
    CheckDuration(FLAGS_duration);
    return true;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "aslam %s: %s\n", command, e.what());
    return false;
  }
}

// --start into `start` (left empty without the flag); false after printing why it is malformed.
bool ParseStartFlag(const char* command, std::optional<Pose2d>* start) {
  if (FLAGS_start.empty()) return true;
  *start = ParsePose(FLAGS_start);
  if (*start) return true;
  std::fprintf(stderr, "aslam %s: --start '%s': expected X,Y,YAW\n", command, FLAGS_start.c_str());
  return false;
}

void PrintWritten(const std::string& dir, const std::vector<std::string>& files,
                  const char* suffix) {
  std::printf("wrote %s/{", dir.c_str());
  for (std::size_t i = 0; i < files.size(); ++i)
    std::printf("%s%s", i ? "," : "", files[i].c_str());
  std::printf("}%s\n", suffix);
}

void PrintProgress(const ExploreProgress& p, bool terminal) {
  char goal[64] = "none";
  if (p.goal_id >= 0)
    std::snprintf(goal, sizeof goal, "#%lld (%.1f, %.1f)", static_cast<long long>(p.goal_id),
                  p.goal_m.x_m, p.goal_m.y_m);
  std::printf(
      "%st=%7.1f s  coverage %5.1f %%  keyframes %5d  closures %4d  frontiers %3d  goal %-18s  "
      "reached %3d failed %3d  collisions %lld  %6.1fx real time  %s%s%s%s",
      terminal ? "\r" : "", p.sim_s, 100.0 * p.coverage, p.keyframes, p.loop_closures, p.frontiers,
      goal, p.goals_reached, p.goals_failed, static_cast<long long>(p.collisions),
      p.wall_s > 0 ? p.sim_s / p.wall_s : 0.0, p.state.c_str(),
      p.restarts.empty() ? "" : "  restarts: ", p.restarts.c_str(), terminal ? "\033[K" : "\n");
  std::fflush(stdout);
}

// With --set: OUT/config.yaml, the run's effective config (--config, the overrides, --method and
// --seed), which the run then reads.
std::string WriteEffectiveConfig(const ExploreOptions& options,
                                 std::vector<ConfigOverride> overrides, const std::string& out) {
  std::string text = "# written by aslam explore: " +
                     (options.config_file.empty() ? "built-in defaults" : options.config_file);
  for (const ConfigOverride& o : overrides) text += " --set " + o.Key() + "=" + o.value;
  text += "; utility.method and sim.seed as --method and --seed\n";
  overrides.push_back(ParseConfigOverride(
      "utility.method=" +
      std::string(UtilityMethodName(ParseExploreMethod(options.method, "--method").utility))));
  overrides.push_back(ParseConfigOverride("sim.seed=" + std::to_string(options.seed)));
  text += ApplyConfigOverrides(options.config_file, overrides);
  std::filesystem::create_directories(out);
  const std::string path = out + "/config.yaml";
  WriteFileAtomically(path, text);
  return path;
}

// Process mode on a host without a multicast route: the same command again in a private
// network namespace whose loopback carries multicast, as scripts/demo does. Returns only if
// that cannot be done, with the exit code.
int RunInPrivateNetworkNamespace(const std::string& lcm_url) {
  if (std::getenv(kPrivateNetnsVariable) != nullptr) {
    std::fprintf(stderr,
                 "aslam explore: no multicast route for %s even in the private network "
                 "namespace: see scripts/in-private-netns\n",
                 lcm_url.c_str());
    return 1;
  }
  std::string why_not = WhyNoPrivateNetworkNamespace();
  if (why_not.empty()) {
    std::printf(
        "aslam explore: this host has no multicast route for %s; running again in a private "
        "network namespace (unshare -rn) whose loopback carries multicast\n",
        lcm_url.c_str());
    why_not = ExecInPrivateNetworkNamespace(g_command_line);
  }
  std::fprintf(stderr,
               "aslam explore: process mode needs LCM's udpm, which needs a multicast route, and "
               "a private network namespace is not possible either (%s). Add a loopback route: "
               "sudo ip link set lo multicast on && sudo ip route add 224.0.0.0/4 dev lo; or run "
               "in one process with --inproc\n",
               why_not.c_str());
  return 1;
}

int Explore(const std::vector<std::string>& sets) {
  if (FLAGS_world.empty() || FLAGS_out.empty()) {
    std::fprintf(stderr, "aslam explore: --world and --out are required\nusage: %s\n", kUsage);
    return 2;
  }
  if (!CheckDurationFlag("explore")) return 2;
  if (FLAGS_seed < 0 || !(FLAGS_rate >= 0) || !std::isfinite(FLAGS_rate)) {
    std::fprintf(stderr, "aslam explore: --seed %lld, --rate %g: both must be finite and >= 0\n",
                 static_cast<long long>(FLAGS_seed), FLAGS_rate);
    return 2;
  }
  if (FLAGS_inproc && !FLAGS_launch.empty()) {
    std::fprintf(stderr, "aslam explore: --launch '%s' is for process mode, not --inproc\n",
                 FLAGS_launch.c_str());
    return 2;
  }
  if (FLAGS_inproc && FLAGS_devices) {
    std::fprintf(stderr, "aslam explore: --devices runs the driver processes: not with --inproc\n");
    return 2;
  }
  ExploreOptions options;
  options.world = FLAGS_world;
  options.method = FLAGS_method;
  options.duration_s = FLAGS_duration;
  options.seed = static_cast<uint64_t>(FLAGS_seed);
  options.config_file = FLAGS_config;
  options.progress_period_s = FLAGS_progress;
  if (!ParseStartFlag("explore", &options.start)) return 2;
  std::vector<ConfigOverride> overrides;
  try {
    for (const std::string& set : sets) {
      overrides.push_back(ParseConfigOverride(set));
      CheckRunOverride(overrides.back());
    }
    if (FLAGS_return_home) overrides.push_back(ParseConfigOverride("utility.return_home=true"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam explore: %s\n", e.what());
    return 2;
  }
  // Same pid after the re-run (exec all the way), so the same private URL.
  const std::string lcm_url = FLAGS_lcm_url.empty() ? PrivateLcmUrl(getpid()) : FLAGS_lcm_url;
  if (!FLAGS_inproc && !MulticastRouteExists(lcm_url)) return RunInPrivateNetworkNamespace(lcm_url);
  const bool terminal = isatty(STDOUT_FILENO) != 0;
  try {
    if (!overrides.empty()) {
      options.config_file = WriteEffectiveConfig(options, overrides, FLAGS_out);
      std::printf("aslam explore: config with %zu --set: %s\n", overrides.size(),
                  options.config_file.c_str());
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    const auto on_progress = [&](const ExploreProgress& p) {
      if (FLAGS_progress > 0) PrintProgress(p, terminal);
    };
    ExploreResult result;
    if (FLAGS_inproc) {
      std::printf("aslam explore: %s, method %s, seed %lld, up to %.0f s simulated, in-process\n",
                  FLAGS_world.c_str(), FLAGS_method.c_str(), static_cast<long long>(FLAGS_seed),
                  FLAGS_duration);
      std::fflush(stdout);
      result = RunExploreInProcess(options, &g_stop, on_progress);
    } else {
      ExploreProcessOptions process;
      process.explore = options;
      process.rate = FLAGS_rate;
      process.lcm_url = lcm_url;
      process.out_dir = FLAGS_out;
      process.launch_file = FLAGS_launch;
      process.devices = FLAGS_devices;
      std::printf(
          "aslam explore: %s, method %s, seed %lld, up to %.0f s simulated, processes at %gx "
          "real time on %s (logs in %s)\n",
          FLAGS_world.c_str(), FLAGS_method.c_str(), static_cast<long long>(FLAGS_seed),
          FLAGS_duration, FLAGS_rate, process.lcm_url.c_str(), FLAGS_out.c_str());
      std::fflush(stdout);
      result = RunExploreProcess(process, &g_stop, on_progress);
    }
    if (terminal && FLAGS_progress > 0) std::printf("\n");
    WriteRunFolder(result, FLAGS_out);
    if (!FLAGS_inproc) {
      // metrics.json says which mode made it.
      WriteFileAtomically(FLAGS_out + "/metrics.json",
                          AddModeToMetricsJson(MetricsToJson(result.metrics), "process"));
      // CPU per process and scan-to-command latency, from the run's own log.
      try {
        const std::string log = FLAGS_out + "/run.lcmlog";
        const LogStats stats = ComputeLogStats(log);
        WriteFileAtomically(FLAGS_out + "/process_stats.json", LogStatsJson(stats));
        std::printf("%s", LogStatsTable(stats).c_str());
        const std::string warning = LogStatsWarning(stats, log);
        if (!warning.empty()) std::fprintf(stderr, "aslam explore: %s\n", warning.c_str());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "aslam explore: no process figures: %s\n", e.what());
      }
    }
    const RunMetrics& m = result.metrics;
    std::printf(
        "aslam explore: %s after %.1f s simulated (%.1f s wall): coverage %.1f %%, ATE RMSE "
        "%.3f m, %d keyframes, %d loop closures, %lld collisions, goals %d reached %d failed\n",
        m.end_reason.c_str(), m.sim_seconds, m.wall_seconds, 100.0 * m.coverage, m.ate_rmse_m,
        m.keyframes, m.loop_closures, static_cast<long long>(m.collisions), m.goals_reached,
        m.goals_failed);
    if (m.node_cpu) {
      const NodeCpu& c = *m.node_cpu;
      std::printf(
          "aslam explore: CPU %.1f s (%.1fx simulated per CPU second): slam %.1f, frontier %.1f, "
          "utility %.1f, nav %.1f, sim %.1f, evaluation %.1f, other %.1f\n",
          c.total_s(), m.sim_per_cpu.value_or(0.0), c.slam_s, c.frontier_s, c.utility_s, c.nav_s,
          c.sim_s, c.evaluation_s, c.other_s);
    }
    std::printf(
        "wrote "
        "%s/"
        "{map.yaml,map.pgm,map.png,graph.g2o,coverage.csv,uncertainty.csv,goals.csv,metrics.json%s%"
        "s}\n",
        FLAGS_out.c_str(),
        FLAGS_inproc ? ",cost.csv" : ",process_stats.json,run.lcmlog,config.yaml,NAME.log",
        FLAGS_inproc && !overrides.empty() ? ",config.yaml" : "");
    if (const std::string restarts = RestartsSummary(m.processes); !restarts.empty()) {
      std::printf("aslam explore: processes restarted during the run: %s (last ends:",
                  restarts.c_str());
      for (const ProcessHistory& p : m.processes) {
        if (p.restarts > 0) std::printf(" %s %s", p.name.c_str(), LastEnd(p).c_str());
      }
      std::printf("; see %s/procman.log)\n", FLAGS_out.c_str());
    }
    if (m.end_reason == "process-failed") {
      std::fprintf(stderr,
                   "aslam explore: the run did not complete: a process failed and procman did not "
                   "bring it back (see %s/procman.log)\n",
                   FLAGS_out.c_str());
      return 1;
    }
    if (m.end_reason == "procman-exited") {
      std::fprintf(stderr,
                   "aslam explore: aslam-procman ended before the run did: see %s/procman.log and "
                   "%s/sim.log\n",
                   FLAGS_out.c_str(), FLAGS_out.c_str());
      return 1;
    }
    return m.end_reason == "interrupted" ? 130 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam explore: %s\n", e.what());
    return 1;
  }
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

std::string Clock(double seconds) {
  if (seconds < 0) return "--:--:--";
  const long s = std::lround(seconds);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buffer;
}

void PrintBenchProgress(const BenchProgress& p, bool terminal) {
  const int done = p.skipped + p.finished + p.failed;
  constexpr int kWidth = 30;
  const int filled = p.total > 0 ? done * kWidth / p.total : 0;
  const std::string queued = p.queued > 0 ? Format(", %d queued", p.queued) : "";
  std::printf("%s[%s%s] %d/%d runs (%d skipped, %d failed, %d running%s)  elapsed %s  ETA %s%s",
              terminal ? "\r" : "", std::string(filled, '#').c_str(),
              std::string(kWidth - filled, '.').c_str(), done, p.total, p.skipped, p.failed,
              p.running, queued.c_str(), Clock(p.elapsed_s).c_str(), Clock(p.eta_s).c_str(),
              terminal ? "\033[K" : "\n");
  std::fflush(stdout);
}

// --slurm's flags; false after printing why they are refused.
bool SlurmFlags(SlurmOptions* slurm) {
  slurm->partition = FLAGS_partition;
  slurm->time_limit = FLAGS_time;
  slurm->memory = FLAGS_mem;
  std::istringstream words(FLAGS_sbatch_args);
  for (std::string word; words >> word;) slurm->sbatch_args.push_back(word);
  // --jobs caps the tasks running at once only when given.
  if (!gflags::GetCommandLineFlagInfoOrDie("jobs").is_default) slurm->max_running = FLAGS_jobs;
  slurm->wait = !FLAGS_no_wait;
  slurm->poll_s = FLAGS_slurm_poll_s;
  try {
    CheckSlurmOptions(*slurm);
    return true;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "aslam bench: %s\n", e.what());
    return false;
  }
}

// This executable's path, which bench's runs execute; "" after printing why it is unknown.
std::string OwnExecutable(const char* command) {
  char self[4096];
  const ssize_t length = readlink("/proc/self/exe", self, sizeof self - 1);
  if (length > 0) return std::string(self, length);
  std::fprintf(stderr, "aslam %s: cannot find its own executable (/proc/self/exe)\n", command);
  return "";
}

int Bench(const std::vector<std::string>& sets) {
  if (!CheckDurationFlag("bench")) return 2;
  BenchOptions options;
  options.sweep = sets;
  options.worlds = SplitList(FLAGS_worlds);
  options.methods = SplitList(FLAGS_methods);
  options.seeds = FLAGS_seeds;
  options.duration_s = FLAGS_duration;
  options.jobs = FLAGS_jobs > 0 ? FLAGS_jobs : std::max(1u, std::thread::hardware_concurrency());
  options.config_file = FLAGS_config;
  options.out_dir = FLAGS_out;
  options.plots = FLAGS_plots;
  options.aslam_binary = OwnExecutable("bench");
  if (options.aslam_binary.empty()) return 1;
  if (!ParseStartFlag("bench", &options.start)) return 2;
  SlurmOptions slurm;
  if (FLAGS_slurm && !SlurmFlags(&slurm)) return 2;
  for (const char* flag : {"partition", "time", "mem", "sbatch_args", "no_wait", "slurm_poll_s"}) {
    if (!FLAGS_slurm && !gflags::GetCommandLineFlagInfoOrDie(flag).is_default) {
      std::fprintf(stderr, "aslam bench: --%s is an option of --slurm, which is not given\n", flag);
      return 2;
    }
  }
  const bool terminal = isatty(STDOUT_FILENO) != 0;
  try {
    const std::vector<BenchRun> runs = PlanBench(options);
    const std::string settings =
        sets.empty() ? "" : std::to_string(PlanSettings(sets).size()) + " settings x ";
    const std::string where =
        FLAGS_slurm ? std::string("as a Slurm array job") : Format("%d at a time", options.jobs);
    std::printf(
        "aslam bench: %zu runs (%s%zu worlds x %zu methods x %d seeds, %.0f s simulated each), %s, "
        "in %s\n",
        runs.size(), settings.c_str(), options.worlds.size(), options.methods.size(), options.seeds,
        options.duration_s, where.c_str(), options.out_dir.c_str());
    std::fflush(stdout);
    if (FLAGS_report_only) {
      const auto finished = std::count_if(runs.begin(), runs.end(), [](const BenchRun& run) {
        return ReadFinishedRun(run).has_value();
      });
      std::printf("aslam bench: %ld of %zu runs finished%s\n", static_cast<long>(finished),
                  runs.size(),
                  finished < static_cast<long>(runs.size())
                      ? "; rerun without --report_only to run the others"
                      : "");
      const std::vector<std::string> written = WriteBenchReports(options);
      PrintWritten(options.out_dir, written, " from the finished runs");
      return 0;
    }
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);
    auto progress = [&](const BenchProgress& p) { PrintBenchProgress(p, terminal); };
    auto message = [&](const std::string& text) {
      std::printf("%saslam bench: %s\n", terminal ? "\r\033[K" : "", text.c_str());
      std::fflush(stdout);
    };
    const BenchSummary summary = FLAGS_slurm
                                     ? RunSlurmBench(options, slurm, &g_stop, progress, message)
                                     : RunBench(options, &g_stop, progress);
    if (FLAGS_slurm && !slurm.wait) {
      std::printf(
          "aslam bench: %d runs already finished; rerun the same command without --no_wait to "
          "wait for the rest and write the reports\n",
          summary.skipped);
      return 0;
    }
    if (terminal) std::printf("\n");
    std::printf(
        "aslam bench: %d runs finished now, %d skipped as already finished, %zu failed, in %s "
        "wall%s\n",
        summary.finished, summary.skipped, summary.failed.size(),
        Clock(summary.wall_seconds).c_str(),
        summary.interrupted ? " (interrupted: rerun the same command to resume)" : "");
    for (const FailedRun& failed : summary.failed) {
      std::string logs;
      for (const std::string& log : failed.logs) logs += (logs.empty() ? "" : ", ") + log;
      std::fprintf(stderr, "aslam bench: run failed: %s: %s; see %s\n", RunName(failed.run).c_str(),
                   failed.why.c_str(), logs.c_str());
    }
    const std::vector<std::string> written = WriteBenchReports(options);
    PrintWritten(options.out_dir, written, "");
    if (summary.interrupted) return 130;
    return summary.failed.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam bench: %s\n", e.what());
    return 1;
  }
}

// `aslam bench-task RUN_LIST N`: one run of a bench's run list (eval/bench_run_list.h).
int BenchTask(const std::vector<std::string>& args) {
  if (args.size() != 2) {
    std::fprintf(stderr, "usage: aslam bench-task RUN_LIST N\n");
    return 2;
  }
  const std::string self = OwnExecutable("bench-task");
  if (self.empty()) return 1;
  return ExecBenchTask(self, args[0], args[1]);
}

int LogStatsCommand(const std::vector<std::string>& paths) {
  if (paths.size() != 1) {
    std::fprintf(stderr, "usage: aslam log-stats RUN/run.lcmlog\n");
    return 2;
  }
  try {
    const LogStats stats = ComputeLogStats(paths[0]);
    std::printf("%s", LogStatsTable(stats).c_str());
    const std::string warning = LogStatsWarning(stats, paths[0]);
    if (!warning.empty()) std::fprintf(stderr, "aslam log-stats: %s\n", warning.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam log-stats: %s\n", e.what());
    return 1;
  }
}

}  // namespace

std::vector<std::string> TakeSetArguments(std::vector<char*>* args) {
  std::vector<std::string> sets;
  for (std::size_t i = 1; i < args->size();) {
    const std::string arg = (*args)[i];
    if (arg == "--") break;  // gflags' end of flags
    const std::size_t dashes = arg.rfind("--", 0) == 0 ? 2 : arg.rfind('-', 0) == 0 ? 1 : 0;
    const std::string name = arg.substr(dashes, arg.find('=') - dashes);
    if (dashes == 0 || name != "set") {
      ++i;
      continue;
    }
    if (arg.find('=') != std::string::npos) {
      sets.push_back(arg.substr(arg.find('=') + 1));
      args->erase(args->begin() + i);
      continue;
    }
    if (i + 1 >= args->size()) throw std::invalid_argument("--set needs KEY=VALUE");
    sets.push_back((*args)[i + 1]);
    args->erase(args->begin() + i, args->begin() + i + 2);
  }
  return sets;
}

// `aslam control COMMAND`: one EXPLORE_CONTROL request, and the utility's answer.
int Control(const std::vector<std::string>& args) {
  const std::optional<ExploreCommand> command =
      args.size() == 1 ? ParseExploreCommand(args[0]) : std::nullopt;
  if (!command) {
    std::fprintf(stderr,
                 "aslam control: expected one of pause, resume, stop, return_home, got '%s'\n",
                 args.empty() ? "" : args[0].c_str());
    return 2;
  }
  if (!(FLAGS_wait >= 0.0) || !std::isfinite(FLAGS_wait)) {
    std::fprintf(stderr, "aslam control: --wait %g: must be finite and >= 0\n", FLAGS_wait);
    return 2;
  }
  const std::string url = ResolveLcmUrl(FLAGS_lcm_url);
  try {
    const std::unique_ptr<lcm::LCM> lcm = OpenLcm(url);
    const std::optional<explore_status_t> answer =
        SendExploreControl(*lcm, *command, "aslam control", FLAGS_wait);
    if (!answer) {
      std::fprintf(stderr,
                   "aslam control: sent %s on %s; no EXPLORE_STATUS came back within %g s: is "
                   "aslam-utility running on this LCM URL?\n",
                   ExploreCommandName(*command), url.c_str(), FLAGS_wait);
      return 1;
    }
    std::printf("%s\n", DescribeExploreStatus(*answer).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aslam control: %s\n", e.what());
    return 1;
  }
  return 0;
}

// `aslam view RUN_FOLDER`: the run's log in aslam-viewer, with a time slider.
int View(const std::vector<std::string>& args) {
  if (args.size() != 1) {
    std::fprintf(stderr, "aslam view: expected one run folder\nusage: %s\n", kUsage);
    return 2;
  }
  const std::string log = args[0] + "/run.lcmlog";
  if (!std::filesystem::exists(log)) {
    std::fprintf(stderr,
                 "aslam view: %s: no such file. Runs in process mode keep their bus in "
                 "run.lcmlog; runs with --inproc (and aslam bench) keep none: run aslam explore "
                 "without --inproc to have one\n",
                 log.c_str());
    return 1;
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  ViewerOptions options;
  options.log_path = log;
  options.port = FLAGS_port;
  options.bind_address = FLAGS_bind;
  return RunViewer(options, g_stop);
}

int RunAslamCommand(int argc, char** argv) {
  const bool help =
      argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0);
  const std::string command = argc >= 2 ? argv[1] : "";
  g_command_line.assign(argv, argv + argc);
  if (command != "explore" && command != "bench" && command != "bench-task" &&
      command != "log-stats" && command != "control" && command != "view") {
    std::fprintf(help ? stdout : stderr,
                 "usage: aslam <command> [flags]\n\ncommands:\n"
                 "  explore     explore a world, write a run folder\n"
                 "  bench       run the paper's experiment matrix, write its tables and figures\n"
                 "  bench-task  one run of a bench's run list (what bench runs, here or on Slurm)\n"
                 "  log-stats   CPU per process and LIDAR_SCAN -> CMD_VEL latency of a run's lcm "
                 "log\n"
                 "  control     pause, resume, stop a running exploration, or send it home\n"
                 "  view        a finished run in the browser, with a time slider\n\n%s\n",
                 kUsage);
    return help ? 0 : 2;
  }
  // The subcommand leaves argv; gflags sees `aslam --flags...`.
  std::vector<char*> args(argv, argv + argc);
  args.erase(args.begin() + 1);
  std::vector<std::string> sets;
  try {
    sets = TakeSetArguments(&args);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "aslam %s: %s\nusage: %s\n", command.c_str(), e.what(), kUsage);
    return 2;
  }
  if ((command == "log-stats" || command == "control" || command == "view" ||
       command == "bench-task") &&
      !sets.empty()) {
    std::fprintf(stderr, "aslam %s: takes no --set\n", command.c_str());
    return 2;
  }
  int n = static_cast<int>(args.size());
  char** v = args.data();
  ParseFlags(&n, &v, kUsage);
  if (command == "log-stats") return LogStatsCommand(std::vector<std::string>(v + 1, v + n));
  if (command == "control") return Control(std::vector<std::string>(v + 1, v + n));
  if (command == "view") return View(std::vector<std::string>(v + 1, v + n));
  if (command == "bench-task") return BenchTask(std::vector<std::string>(v + 1, v + n));
  if (n > 1) {
    std::fprintf(stderr, "aslam %s: unexpected argument '%s'\n", command.c_str(), v[1]);
    return 2;
  }
  if (command == "bench") {
    if (FLAGS_out.empty()) {
      std::fprintf(stderr, "aslam bench: --out is required\nusage: %s\n", kUsage);
      return 2;
    }
    return Bench(sets);
  }
  return Explore(sets);
}

}  // namespace aslam
