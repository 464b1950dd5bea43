#include "eval/log_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <lcm/lcm-cpp.hpp>

#include "aslam/lidar_scan_t.hpp"
#include "aslam/lidar_scan_v1_t.hpp"
#include "aslam/procman_status_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/channels.h"
#include "common/json_text.h"
#include "common/text_format.h"
#include "eval/stats.h"
#include "procman/procman_lcm.h"

namespace aslam {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kBytesPerMib = 1024.0 * 1024.0;
// An event on disk: sync word, event number, timestamp, channel length, data length (4 + 8 + 8
// + 4 + 4 bytes), then the channel and the data.
constexpr int64_t kEventHeaderBytes = 28;

// lcm-gen's decode returns < 0 for bad bytes, but a corrupt array count can
// still make it resize a vector to an absurd size and throw; both are one
// undecodable message, never the end of the analysis.
template <typename MsgT>
bool Decode(const lcm::LogEvent& event, MsgT* msg) {
  try {
    return msg->decode(event.data, 0, event.datalen) >= 0;
  } catch (const std::exception&) {
    return false;
  }
}

// Pairs each CMD_VEL with the LIDAR_SCAN of its utime. Scans are forgotten
// kScanMatchWindowSeconds after they were logged, so a 30-minute log needs
// only a few hundred entries.
class ScanMatcher {
 public:
  void AddScan(int64_t utime, int64_t logged_us) {
    Forget(logged_us);
    logged_us_by_utime_[utime] = logged_us;  // a repeated utime (sim restart): the newest wins
    arrival_order_.emplace_back(logged_us, utime);
  }

  void AddCommand(int64_t utime, int64_t logged_us) {
    Forget(logged_us);
    const auto it = logged_us_by_utime_.find(utime);
    if (it == logged_us_by_utime_.end()) {
      ++unmatched_;
      return;
    }
    latencies_ms_.push_back((logged_us - it->second) / 1e3);
    // One answer per scan: a second command with this utime (the stop at
    // shutdown) must not count as a late answer.
    logged_us_by_utime_.erase(it);
  }

  std::vector<double>& latencies_ms() { return latencies_ms_; }
  int64_t unmatched() const { return unmatched_; }

 private:
  void Forget(int64_t now_us) {
    const int64_t oldest_kept_us = now_us - static_cast<int64_t>(kScanMatchWindowSeconds * 1e6);
    while (!arrival_order_.empty() && arrival_order_.front().first < oldest_kept_us) {
      const auto [logged_us, utime] = arrival_order_.front();
      arrival_order_.pop_front();
      const auto it = logged_us_by_utime_.find(utime);
      // Only if this entry is still the one that arrival recorded (not answered, not replaced).
      if (it != logged_us_by_utime_.end() && it->second == logged_us) logged_us_by_utime_.erase(it);
    }
  }

  std::unordered_map<int64_t, int64_t> logged_us_by_utime_;
  std::deque<std::pair<int64_t, int64_t>> arrival_order_;  // (logged_us, utime)
  std::vector<double> latencies_ms_;
  int64_t unmatched_ = 0;
};

struct CpuAccumulator {
  int samples = 0;
  double sum_cpu_percent = 0;
  double max_cpu_percent = 0;
  int64_t max_rss_bytes = 0;
};

// A table cell: the number, or "-" where there is none.
std::string Cell(double value, const char* format) {
  if (!std::isfinite(value)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

LogStats ComputeLogStats(const std::string& lcmlog_path) {
  lcm::LogFile log(lcmlog_path, "r");
  if (!log.good()) throw std::runtime_error("cannot open lcm log " + lcmlog_path);

  LogStats stats;
  std::error_code size_error;
  const auto file_bytes = std::filesystem::file_size(lcmlog_path, size_error);
  if (size_error) {
    throw std::runtime_error("cannot read the size of " + lcmlog_path + ": " +
                             size_error.message());
  }
  stats.file_bytes = static_cast<int64_t>(file_bytes);
  ScanMatcher matcher;
  std::map<std::string, CpuAccumulator> cpu_by_name;  // every name seen, RUNNING or not
  std::map<std::string, ChannelTraffic> traffic;
  ProcessHistoryTracker history;
  int64_t& events = stats.events;
  int64_t first_us = 0;
  int64_t last_us = 0;

  for (const lcm::LogEvent* event = log.readNextEvent(); event != nullptr;
       event = log.readNextEvent()) {
    // LCM reads up to the next sync word, skipping what is not an event, and ends at the first
    // incomplete one as at the end of the file: positions tell the two apart.
    const int64_t end = ftello(log.getFilePtr());
    stats.skipped_bytes += end - stats.read_bytes - kEventHeaderBytes -
                           static_cast<int64_t>(event->channel.size()) - event->datalen;
    stats.read_bytes = end;
    // min/max rather than first/last: the logger's wall clock may step back.
    first_us = events == 0 ? event->timestamp : std::min(first_us, event->timestamp);
    last_us = events == 0 ? event->timestamp : std::max(last_us, event->timestamp);
    ++events;
    ChannelTraffic& channel = traffic[event->channel];
    ++channel.messages;
    channel.bytes += event->datalen;
    channel.largest_bytes = std::max<int64_t>(channel.largest_bytes, event->datalen);

    if (event->channel == channels::kLidarScan) {
      lidar_scan_t scan;
      lidar_scan_v1_t legacy_scan;  // a log from before beam times
      if (Decode(*event, &scan)) {
        matcher.AddScan(scan.utime, event->timestamp);
      } else if (Decode(*event, &legacy_scan)) {
        matcher.AddScan(legacy_scan.utime, event->timestamp);
      } else {
        ++stats.undecodable;
        continue;
      }
    } else if (event->channel == channels::kCmdVel) {
      velocity_command_t command;
      if (!Decode(*event, &command)) {
        ++stats.undecodable;
        continue;
      }
      matcher.AddCommand(command.utime, event->timestamp);
    } else if (event->channel == channels::kProcmanStatus) {
      procman_status_t status;
      if (!Decode(*event, &status)) {
        ++stats.undecodable;
        continue;
      }
      DeputyStatus deputy;
      if (FromLcm(status, &deputy)) history.Add(deputy);
      for (const procman_process_status_t& p : status.processes) {
        CpuAccumulator& acc = cpu_by_name[p.name];
        // A NaN from a broken deputy would poison the mean; such a sample says nothing.
        if (p.state != procman_process_status_t::STATE_RUNNING || !std::isfinite(p.cpu_percent))
          continue;
        ++acc.samples;
        acc.sum_cpu_percent += p.cpu_percent;
        acc.max_cpu_percent =
            acc.samples == 1 ? p.cpu_percent : std::max(acc.max_cpu_percent, p.cpu_percent);
        acc.max_rss_bytes = std::max(acc.max_rss_bytes, p.rss_bytes);
      }
    }
  }
  if (events == 0) {
    throw std::runtime_error("no whole lcm event in " + lcmlog_path +
                             " (empty, not an lcm log, or cut short within its first event)");
  }
  stats.truncated = stats.read_bytes < stats.file_bytes;
  stats.log_seconds = (last_us - first_us) / 1e6;
  for (auto& [name, channel] : traffic) {
    channel.channel = name;
    stats.channels.push_back(std::move(channel));
  }
  std::stable_sort(
      stats.channels.begin(), stats.channels.end(),
      [](const ChannelTraffic& a, const ChannelTraffic& b) { return a.bytes > b.bytes; });

  for (const auto& [name, acc] : cpu_by_name) {
    ProcessCpu p;
    p.name = name;
    p.samples = acc.samples;
    for (const ProcessHistory& h : history.processes()) {
      if (h.name == name) p.history = h;
    }
    if (acc.samples > 0) {
      p.mean_cpu_percent = acc.sum_cpu_percent / acc.samples;
      p.max_cpu_percent = acc.max_cpu_percent;
      p.max_rss_mib = acc.max_rss_bytes / kBytesPerMib;
      stats.total_mean_cpu_percent += p.mean_cpu_percent;
    }
    stats.processes.push_back(std::move(p));
  }
  for (ProcessCpu& p : stats.processes) {
    // 0/0 (nothing used any CPU) stays NaN: there is no share to speak of.
    if (p.samples > 0 && stats.total_mean_cpu_percent > 0) {
      p.share = p.mean_cpu_percent / stats.total_mean_cpu_percent;
    }
  }
  // Highest mean first; processes that never ran last; ties by name so the order is reproducible.
  std::stable_sort(stats.processes.begin(), stats.processes.end(),
                   [](const ProcessCpu& a, const ProcessCpu& b) {
                     const bool a_ran = a.samples > 0;
                     const bool b_ran = b.samples > 0;
                     if (a_ran != b_ran) return a_ran;
                     if (a_ran && a.mean_cpu_percent != b.mean_cpu_percent)
                       return a.mean_cpu_percent > b.mean_cpu_percent;
                     return false;  // cpu_by_name is ordered by name already
                   });

  std::vector<double>& latencies_ms = matcher.latencies_ms();
  std::sort(latencies_ms.begin(), latencies_ms.end());
  LatencyStats& latency = stats.scan_to_cmd_vel;
  latency.matched = static_cast<int64_t>(latencies_ms.size());
  latency.unmatched_commands = matcher.unmatched();
  latency.median_ms = NearestRankPercentile(latencies_ms, 0.5);
  latency.p99_ms = NearestRankPercentile(latencies_ms, 0.99);
  latency.max_ms = latencies_ms.empty() ? kNaN : latencies_ms.back();
  return stats;
}

std::string LogStatsWarning(const LogStats& stats, const std::string& lcmlog_path) {
  std::string warning;
  if (stats.truncated) {
    warning = Format(
        "warning: %s is truncated or corrupt: reading stopped at byte %lld of %lld, after %lld "
        "whole events; the figures leave out the last %lld bytes",
        lcmlog_path.c_str(), static_cast<long long>(stats.read_bytes),
        static_cast<long long>(stats.file_bytes), static_cast<long long>(stats.events),
        static_cast<long long>(stats.file_bytes - stats.read_bytes));
  }
  if (stats.skipped_bytes > 0) {
    warning += std::string(warning.empty() ? "warning: " + lcmlog_path : ";") +
               Format(" %lld bytes between events were not an event and were skipped",
                      static_cast<long long>(stats.skipped_bytes));
  }
  return warning;
}

std::string LogStatsTable(const LogStats& stats) {
  std::string out;
  char line[256];
  std::size_t name_width = 7;  // "process"
  for (const ProcessCpu& p : stats.processes) name_width = std::max(name_width, p.name.size());
  const int w = static_cast<int>(name_width);
  std::snprintf(line, sizeof line, "%-*s %10s %10s %7s %12s %8s %8s\n", w, "process", "mean CPU %",
                "max CPU %", "share", "max RSS MiB", "restarts", "last end");
  out += line;
  for (const ProcessCpu& p : stats.processes) {
    std::snprintf(line, sizeof line, "%-*s %10s %10s %7s %12s %8d %8s\n", w, p.name.c_str(),
                  Cell(p.mean_cpu_percent, "%.1f").c_str(), Cell(p.max_cpu_percent, "%.1f").c_str(),
                  Cell(100.0 * p.share, "%.1f%%").c_str(), Cell(p.max_rss_mib, "%.1f").c_str(),
                  p.history.restarts, LastEnd(p.history).c_str());
    out += line;
  }
  if (stats.processes.empty()) {
    out += "(no PROCMAN_STATUS in the log)\n";
  } else {
    std::snprintf(line, sizeof line, "%-*s %10s\n", w, "total",
                  Cell(stats.total_mean_cpu_percent, "%.1f").c_str());
    out += line;
  }
  const LatencyStats& l = stats.scan_to_cmd_vel;
  std::snprintf(line, sizeof line,
                "LIDAR_SCAN -> CMD_VEL: median %s ms, p99 %s ms, max %s ms (%lld matched, %lld "
                "unmatched commands)\n",
                Cell(l.median_ms, "%.2f").c_str(), Cell(l.p99_ms, "%.2f").c_str(),
                Cell(l.max_ms, "%.2f").c_str(), static_cast<long long>(l.matched),
                static_cast<long long>(l.unmatched_commands));
  out += line;
  std::size_t channel_width = 7;  // "channel"
  for (const ChannelTraffic& c : stats.channels) {
    channel_width = std::max(channel_width, c.channel.size());
  }
  const int cw = static_cast<int>(channel_width);
  out += Format("%-*s %9s %9s %11s\n", cw, "channel", "messages", "MiB", "largest kB");
  for (const ChannelTraffic& c : stats.channels) {
    out += Format("%-*s %9lld %9.2f %11.1f\n", cw, c.channel.c_str(),
                  static_cast<long long>(c.messages), c.bytes / kBytesPerMib,
                  c.largest_bytes / 1024.0);
  }
  std::snprintf(line, sizeof line, "log: %.1f s, %lld undecodable messages\n", stats.log_seconds,
                static_cast<long long>(stats.undecodable));
  out += line;
  if (stats.truncated) {
    out += Format("log: TRUNCATED: read %lld whole events, stopped at byte %lld of %lld\n",
                  static_cast<long long>(stats.events), static_cast<long long>(stats.read_bytes),
                  static_cast<long long>(stats.file_bytes));
  }
  if (stats.skipped_bytes > 0) {
    out += Format("log: %lld bytes between events skipped\n",
                  static_cast<long long>(stats.skipped_bytes));
  }
  return out;
}

std::string LogStatsJson(const LogStats& stats) {
  std::string processes = "[";
  for (std::size_t i = 0; i < stats.processes.size(); ++i) {
    const ProcessCpu& p = stats.processes[i];
    processes += i == 0 ? "\n    " : ",\n    ";
    std::vector<std::pair<std::string, std::string>> fields = {
        {"name", JsonString(p.name)},
        {"samples", std::to_string(p.samples)},
        {"mean_cpu_percent", JsonNumber(p.mean_cpu_percent)},
        {"max_cpu_percent", JsonNumber(p.max_cpu_percent)},
        {"share", JsonNumber(p.share)},
        {"max_rss_mib", JsonNumber(p.max_rss_mib)},
    };
    for (auto& field : ProcessHistoryJsonFields(p.history)) fields.push_back(std::move(field));
    processes += JsonObject(fields);
  }
  processes += stats.processes.empty() ? "]" : "\n  ]";
  std::string channels = "[";
  for (std::size_t i = 0; i < stats.channels.size(); ++i) {
    const ChannelTraffic& c = stats.channels[i];
    channels += i == 0 ? "\n    " : ",\n    ";
    channels += JsonObject({{"channel", JsonString(c.channel)},
                            {"messages", std::to_string(c.messages)},
                            {"bytes", std::to_string(c.bytes)},
                            {"largest_bytes", std::to_string(c.largest_bytes)}});
  }
  channels += stats.channels.empty() ? "]" : "\n  ]";
  const LatencyStats& l = stats.scan_to_cmd_vel;
  const std::vector<std::pair<std::string, std::string>> fields = {
      {"log_seconds", JsonNumber(stats.log_seconds)},
      {"undecodable", std::to_string(stats.undecodable)},
      {"events", std::to_string(stats.events)},
      {"truncated", stats.truncated ? "true" : "false"},
      {"read_bytes", std::to_string(stats.read_bytes)},
      {"file_bytes", std::to_string(stats.file_bytes)},
      {"skipped_bytes", std::to_string(stats.skipped_bytes)},
      {"total_mean_cpu_percent", JsonNumber(stats.total_mean_cpu_percent)},
      {"processes", processes},
      {"scan_to_cmd_vel", JsonObject({
                              {"matched", std::to_string(l.matched)},
                              {"unmatched_commands", std::to_string(l.unmatched_commands)},
                              {"median_ms", JsonNumber(l.median_ms)},
                              {"p99_ms", JsonNumber(l.p99_ms)},
                              {"max_ms", JsonNumber(l.max_ms)},
                          })},
      {"channels", channels},
  };
  std::string out = "{\n";
  for (std::size_t i = 0; i < fields.size(); ++i) {
    out += "  " + JsonString(fields[i].first) + ": " + fields[i].second;
    out += i + 1 < fields.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

}  // namespace aslam
