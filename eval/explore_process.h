#pragma once

// `aslam explore` in process mode (the default, docs/architecture.md §4): aslam-procman
// deputy runs config/launch/explore.yaml (sim, slam, frontier, utility, nav
// and lcm-logger) on a private LCM URL, with the run folder as its log
// folder, so the run folder holds run.lcmlog and each process's log. This
// runner listens on the same URL, for evaluation only (SIM_TRUTH and
// SIM_STATUS for coverage and ATE, docs/architecture.md §6), prints progress and, at the
// end (EXPLORE_STATUS done, the duration, Ctrl-C or the deputy ending),
// stops the deputy with SIGTERM, waits for it and returns the same result as
// the in-process runner: the final map and graph are the last SLAM_MAP and
// POSE_GRAPH heard.

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "eval/explore_runner.h"

namespace aslam {

struct ExploreProcessOptions {
  ExploreOptions explore;  // world, start, method, duration, seed, config, progress
  double rate = 1.0;       // the simulator's real-time factor
  std::string lcm_url;     // "" = PrivateLcmUrl(getpid())
  std::string out_dir;     // the run folder: the deputy's log folder (created)
  // Devices in the loop: the real drivers talk to emulated devices (aslam-sim --devices);
  // the default launch file is then SOURCE/config/launch/explore_devices.yaml.
  bool devices = false;
  std::string launch_file;          // "" = SOURCE/config/launch/explore.yaml
  std::string build_dir;            // "" = the build folder holding this binary (BUILD/eval/aslam)
  double startup_timeout_s = 20.0;  // wall seconds to wait for the simulator's first message
  double stop_timeout_s = 15.0;     // wall seconds from SIGTERM to SIGKILL of the deputy
};

// udpm://239.255.76.67:PORT?ttl=0&recv_buf_size=4194304 with a port derived from
// `pid` (17000..26999).
std::string PrivateLcmUrl(int pid);

// Runs one exploration as processes. Writes OUT/config.yaml (the config with
// utility.method set, what the nodes read) and lets the deputy write
// OUT/run.lcmlog, OUT/NAME.log and OUT/procman.log; the caller writes the run
// folder's outputs (WriteRunFolder). The runner follows PROCMAN_STATUS:
// result.metrics.processes holds each process's restarts and how it last ended
// on its own, and a process that ended and that procman will not restart
// (failed with restart never, procman gave up, or exited) ends the run at
// once. result.metrics.end_reason is then process-failed; otherwise done,
// duration, interrupted or procman-exited (the deputy ended before the
// duration). Throws std::invalid_argument for bad options, std::runtime_error
// if procman cannot be started or the simulator is never heard.
ExploreResult RunExploreProcess(
    const ExploreProcessOptions& options, const std::atomic<bool>* stop = nullptr,
    const std::function<void(const ExploreProgress&)>& on_progress = {});

// False when `url` is udpm:// and this host cannot route a datagram to its multicast group:
// no multicast route (an isolated machine), where LCM's udpm cannot open. Any other URL: true.
// Probes the way LCM does (connect() of a UDP socket to the group), printing nothing.
bool MulticastRouteExists(const std::string& url);

// Set in the environment of a process re-run in a private network namespace.
inline constexpr const char* kPrivateNetnsVariable = "ASLAM_IN_PRIVATE_NETNS";

// "" when this user may make a private network namespace (unshare -rn); otherwise why not.
std::string WhyNoPrivateNetworkNamespace();

// Replaces this process by `argv` run inside a private network namespace whose loopback
// carries multicast (scripts/in-private-netns: unshare -rn, lo up with multicast, a route for
// 224.0.0.0/4 on lo; ttl=0 keeps everything on this host), with kPrivateNetnsVariable set.
// argv[0] is this program: /proc/self/exe is run in its place. Returns only when that cannot
// be done, saying why.
std::string ExecInPrivateNetworkNamespace(const std::vector<std::string>& argv);

// Adds `"mode": "process"` (or any mode) to metrics.json's text as its last key.
std::string AddModeToMetricsJson(const std::string& json, const std::string& mode);

}  // namespace aslam
