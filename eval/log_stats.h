#pragma once

// What a process-mode run's lcm log (run.lcmlog, written by lcm-logger under
// procman, docs/architecture.md §4) says about the processes themselves: how much CPU and
// memory each used (PROCMAN_STATUS) and how long aslam-nav took from a
// LIDAR_SCAN to the CMD_VEL it answered it with. Times are the logger's
// receive timestamps (wall clock, µs), so they include transport; message
// utimes (simulated time) serve only to pair a command with its scan.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "procman/process_history.h"

namespace aslam {

// One supervised process, over the PROCMAN_STATUS samples in which it was
// RUNNING (a stopped, failed or restarting process uses no CPU worth
// averaging). Processes are keyed by name: with several deputies, samples of
// one name are pooled.
struct ProcessCpu {
  std::string name;
  int samples = 0;  // RUNNING samples; 0 if the process never ran (then the figures are NaN)
  double mean_cpu_percent = std::numeric_limits<double>::quiet_NaN();  // 100 = one core
  double max_cpu_percent = std::numeric_limits<double>::quiet_NaN();
  double share = std::numeric_limits<double>::quiet_NaN();  // mean / sum of every process's mean
  double max_rss_mib = std::numeric_limits<double>::quiet_NaN();  // MiB = 2^20 bytes
  ProcessHistory history;  // restarts and how it last ended on its own
};

// Scan-to-command latency: CMD_VEL receive time − receive time of the
// LIDAR_SCAN with the same utime (aslam-nav answers each scan with exactly
// one CMD_VEL stamped with the scan's utime). Percentiles are nearest rank:
// the p-th percentile of n values is the ceil(p·n)-th smallest, so it is
// always a measured value; the median is p = 0.5.
struct LatencyStats {
  int64_t matched = 0;
  // CMD_VELs with no logged scan of their utime left to answer: the scan was
  // lost, it is older than the matching window (kScanMatchWindowSeconds), or
  // it was already answered — aslam-nav's stop command at shutdown carries
  // the latest input time, i.e. repeats an answered scan's utime.
  int64_t unmatched_commands = 0;
  double median_ms = std::numeric_limits<double>::quiet_NaN();  // NaN when nothing matched
  double p99_ms = std::numeric_limits<double>::quiet_NaN();
  double max_ms = std::numeric_limits<double>::quiet_NaN();
};

// One channel's messages in the log (payload bytes, without the event headers).
struct ChannelTraffic {
  std::string channel;
  int64_t messages = 0;
  int64_t bytes = 0;
  int64_t largest_bytes = 0;
};

struct LogStats {
  double log_seconds = 0;             // first to last event, logger time
  std::vector<ProcessCpu> processes;  // highest mean CPU first; never-RUNNING ones last
  double total_mean_cpu_percent = 0;  // sum of the processes' means
  LatencyStats scan_to_cmd_vel;
  // LIDAR_SCAN, CMD_VEL and PROCMAN_STATUS events whose bytes do not decode
  // as their type; skipped. Other channels are not decoded.
  int64_t undecodable = 0;
  int64_t events = 0;      // whole events read
  int64_t file_bytes = 0;  // the file's size when it was opened
  int64_t read_bytes = 0;  // where reading stopped: the end of the last whole event
  // The file goes on past the last whole event: cut short (a crash, a full disk, a copy
  // in progress) or corrupt there. The figures cover the first read_bytes only.
  bool truncated = false;
  // Bytes between events that were not an event header, skipped to find the next one.
  int64_t skipped_bytes = 0;
  std::vector<ChannelTraffic> channels;  // every channel, most bytes first (ties by name)
};

// A scan is kept for matching this long (logger time) after it was logged,
// which bounds memory; a command answering an older scan counts as unmatched.
inline constexpr double kScanMatchWindowSeconds = 10.0;

// Reads the lcm log at `lcmlog_path` once. Throws std::runtime_error naming
// the file if it cannot be opened, is not an lcm log or holds no whole event.
// A log without PROCMAN_STATUS or CMD_VEL gives no processes or NaN latencies.
// A log cut short is read up to its last whole event (`truncated`).
LogStats ComputeLogStats(const std::string& lcmlog_path);

// "" for a log read to its end; otherwise one line naming `lcmlog_path`, the
// byte offset where reading stopped and the bytes left unread (or skipped).
std::string LogStatsWarning(const LogStats& stats, const std::string& lcmlog_path);

// A text table: process | mean CPU % | max CPU % | share | max RSS MiB | restarts | last end, a
// total row, then the latency line, a channel | messages | MiB | largest kB table and the
// log length (and where a truncated log stopped). NaN shows as "-".
std::string LogStatsTable(const LogStats& stats);

// One JSON object, keys in a fixed order, one per line (processes one per
// line); NaN is null. Same stats, same text.
std::string LogStatsJson(const LogStats& stats);

}  // namespace aslam
