#include "eval/log_stats.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "aslam/lidar_scan_t.hpp"
#include "aslam/procman_status_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/channels.h"
#include "common/lcm_log_writer.h"
#include "common/test_temp_dir.h"

namespace aslam {
namespace {

constexpr int64_t kStartUs = 1'700'000'000'000'000;  // a wall-clock epoch, as lcm-logger writes
constexpr double kMib = 1024.0 * 1024.0;

// Bytes that are not a message, as a log may hold them.
void WriteRawBytes(LcmLogWriter* log, const std::string& channel, int64_t logged_us,
                   std::vector<uint8_t> bytes) {
  log->WriteBytes(channel, logged_us, bytes.data(), static_cast<int32_t>(bytes.size()));
}

lidar_scan_t Scan(int64_t utime) {
  lidar_scan_t scan{};
  scan.utime = utime;
  scan.num_ranges = 3;
  scan.range_m = {1.0f, 2.0f, 0.0f};
  return scan;
}

velocity_command_t Command(int64_t utime) {
  velocity_command_t command{};
  command.utime = utime;
  command.linear_mps = 0.2;
  return command;
}

procman_process_status_t Process(const std::string& name, int8_t state, double cpu_percent,
                                 int64_t rss_bytes) {
  procman_process_status_t p{};
  p.name = name;
  p.state = state;
  p.should_run = true;
  p.pid = state == procman_process_status_t::STATE_RUNNING ? 1234 : 0;
  p.cpu_percent = cpu_percent;
  p.rss_bytes = rss_bytes;
  return p;
}

procman_status_t Status(const std::string& deputy,
                        std::vector<procman_process_status_t> processes) {
  procman_status_t status{};
  status.deputy = deputy;
  status.pid = 99;
  status.num_processes = static_cast<int32_t>(processes.size());
  status.processes = std::move(processes);
  return status;
}

constexpr int8_t kRunning = procman_process_status_t::STATE_RUNNING;

// 100 scans, each answered i ms after it was logged (i = 1..100 in a
// shuffled order): nearest-rank median = 50th smallest = 50 ms, p99 = 99th
// smallest = 99 ms, max 100 ms.
TEST(ComputeLogStats, ScanToCommandLatencyOverKnownDelays) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    for (int i = 0; i < 100; ++i) {
      const int64_t utime = 5'000'000 + i * 100'000;          // 10 Hz simulated time
      const int64_t scan_logged_us = kStartUs + i * 200'000;  // half real time: 200 ms apart
      const int delay_ms = (i * 37) % 100 + 1;  // 37 is prime to 100: a permutation of 1..100
      log.Write(channels::kLidarScan, scan_logged_us, Scan(utime));
      log.Write(channels::kCmdVel, scan_logged_us + delay_ms * 1000, Command(utime));
    }
  }
  const LogStats stats = ComputeLogStats(log_path);
  const LatencyStats& l = stats.scan_to_cmd_vel;
  EXPECT_EQ(l.matched, 100);
  EXPECT_EQ(l.unmatched_commands, 0);
  EXPECT_DOUBLE_EQ(l.median_ms, 50.0);
  EXPECT_DOUBLE_EQ(l.p99_ms, 99.0);
  EXPECT_DOUBLE_EQ(l.max_ms, 100.0);
  // First event: scan 0 at +0; last: command 99 at +99·200 ms + (99·37 mod 100 + 1) ms = 19.8 s +
  // 64 ms.
  EXPECT_DOUBLE_EQ(stats.log_seconds, 19.864);
  EXPECT_EQ(stats.undecodable, 0);
  EXPECT_TRUE(stats.processes.empty());  // no PROCMAN_STATUS
  EXPECT_EQ(stats.total_mean_cpu_percent, 0.0);
}

TEST(ComputeLogStats, CommandWithoutItsScanIsUnmatched) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    log.Write(channels::kLidarScan, kStartUs, Scan(1'000'000));
    log.Write(channels::kCmdVel, kStartUs + 4'000, Command(1'000'000));   // 4 ms
    log.Write(channels::kCmdVel, kStartUs + 50'000, Command(1'050'000));  // no scan at this utime
    log.Write(channels::kLidarScan, kStartUs + 100'000, Scan(1'100'000));
    log.Write(channels::kCmdVel, kStartUs + 106'000, Command(1'100'000));  // 6 ms
  }
  const LatencyStats l = ComputeLogStats(log_path).scan_to_cmd_vel;
  EXPECT_EQ(l.matched, 2);
  EXPECT_EQ(l.unmatched_commands, 1);
  EXPECT_DOUBLE_EQ(l.median_ms, 4.0);  // ceil(0.5·2) = 1st of {4, 6}
  EXPECT_DOUBLE_EQ(l.p99_ms, 6.0);
  EXPECT_DOUBLE_EQ(l.max_ms, 6.0);
}

// aslam-nav's stop at shutdown carries the latest input time, i.e. the utime
// of a scan it already answered; it is not a 2-second answer to that scan.
TEST(ComputeLogStats, SecondCommandForAnAnsweredScanIsUnmatched) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    log.Write(channels::kLidarScan, kStartUs, Scan(7'000'000));
    log.Write(channels::kCmdVel, kStartUs + 3'000, Command(7'000'000));
    log.Write(channels::kCmdVel, kStartUs + 2'000'000, Command(7'000'000));  // the stop
  }
  const LatencyStats l = ComputeLogStats(log_path).scan_to_cmd_vel;
  EXPECT_EQ(l.matched, 1);
  EXPECT_EQ(l.unmatched_commands, 1);
  EXPECT_DOUBLE_EQ(l.max_ms, 3.0);
}

// Scans are kept kScanMatchWindowSeconds (10 s) of log time, no longer.
TEST(ComputeLogStats, ScanOlderThanTheWindowIsForgotten) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    log.Write(channels::kLidarScan, kStartUs, Scan(100));
    log.Write(channels::kLidarScan, kStartUs + 1'000'000, Scan(200));
    log.Write(channels::kCmdVel, kStartUs + 10'500'000,
              Command(100));  // 10.5 s after its scan: forgotten
    log.Write(channels::kCmdVel, kStartUs + 10'900'000,
              Command(200));  // 9.9 s after its scan: kept
  }
  const LatencyStats l = ComputeLogStats(log_path).scan_to_cmd_vel;
  EXPECT_EQ(l.matched, 1);
  EXPECT_EQ(l.unmatched_commands, 1);
  EXPECT_DOUBLE_EQ(l.max_ms, 9900.0);
}

// Two deputies. RUNNING samples: aslam-slam 60, 80, 100 % (mean 80, max 100);
// aslam-nav 20, 30 % (mean 25) plus one BACKOFF sample at 90 % that must not
// count; aslam-sim 10, 20, 30 % (mean 20). Sum of means 125: shares 0.64,
// 0.2, 0.16. aslam-viewer never runs: listed last, without figures.
TEST(ComputeLogStats, CpuMeansOverRunningSamplesSortedWithShares) {
  constexpr int8_t kBackoff = procman_process_status_t::STATE_BACKOFF;
  constexpr int8_t kFailed = procman_process_status_t::STATE_FAILED;
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    const int64_t mib = 1024 * 1024;
    log.Write(channels::kProcmanStatus, kStartUs,
              Status("robot", {Process("aslam-slam", kRunning, 60.0, 100 * mib),
                               Process("aslam-nav", kRunning, 20.0, 30 * mib)}));
    log.Write(channels::kProcmanStatus, kStartUs + 10'000,
              Status("base", {Process("aslam-sim", kRunning, 10.0, 50 * mib),
                              Process("aslam-viewer", kFailed, 0.0, 0)}));
    log.Write(channels::kProcmanStatus, kStartUs + 1'000'000,
              Status("robot", {Process("aslam-slam", kRunning, 100.0, 250 * mib),
                               Process("aslam-nav", kBackoff, 90.0, 900 * mib)}));
    log.Write(channels::kProcmanStatus, kStartUs + 1'010'000,
              Status("base", {Process("aslam-sim", kRunning, 20.0, 40 * mib),
                              Process("aslam-viewer", kFailed, 0.0, 0)}));
    log.Write(channels::kProcmanStatus, kStartUs + 2'000'000,
              Status("robot", {Process("aslam-slam", kRunning, 80.0, 200 * mib),
                               Process("aslam-nav", kRunning, 30.0, 32 * mib)}));
    log.Write(channels::kProcmanStatus, kStartUs + 2'010'000,
              Status("base", {Process("aslam-sim", kRunning, 30.0, 45 * mib),
                              Process("aslam-viewer", kFailed, 0.0, 0)}));
  }
  const LogStats stats = ComputeLogStats(log_path);
  ASSERT_EQ(stats.processes.size(), 4u);
  const ProcessCpu& slam = stats.processes[0];
  const ProcessCpu& nav = stats.processes[1];
  const ProcessCpu& sim = stats.processes[2];
  const ProcessCpu& viewer = stats.processes[3];
  EXPECT_EQ(slam.name, "aslam-slam");
  EXPECT_EQ(nav.name, "aslam-nav");
  EXPECT_EQ(sim.name, "aslam-sim");
  EXPECT_EQ(viewer.name, "aslam-viewer");

  EXPECT_EQ(slam.samples, 3);
  EXPECT_DOUBLE_EQ(slam.mean_cpu_percent, 80.0);
  EXPECT_DOUBLE_EQ(slam.max_cpu_percent, 100.0);
  EXPECT_DOUBLE_EQ(slam.max_rss_mib, 250.0);
  EXPECT_EQ(nav.samples, 2);
  EXPECT_DOUBLE_EQ(nav.mean_cpu_percent, 25.0);
  EXPECT_DOUBLE_EQ(nav.max_cpu_percent, 30.0);
  EXPECT_DOUBLE_EQ(nav.max_rss_mib, 32.0);  // the BACKOFF sample's 900 MiB does not count either
  EXPECT_EQ(sim.samples, 3);
  EXPECT_DOUBLE_EQ(sim.mean_cpu_percent, 20.0);
  EXPECT_DOUBLE_EQ(sim.max_cpu_percent, 30.0);
  EXPECT_DOUBLE_EQ(sim.max_rss_mib, 50.0);

  EXPECT_DOUBLE_EQ(stats.total_mean_cpu_percent, 125.0);
  EXPECT_DOUBLE_EQ(slam.share, 0.64);
  EXPECT_DOUBLE_EQ(nav.share, 0.2);
  EXPECT_DOUBLE_EQ(sim.share, 0.16);
  EXPECT_DOUBLE_EQ(slam.share + nav.share + sim.share, 1.0);

  EXPECT_EQ(viewer.samples, 0);
  EXPECT_TRUE(std::isnan(viewer.mean_cpu_percent));
  EXPECT_TRUE(std::isnan(viewer.share));

  EXPECT_DOUBLE_EQ(stats.log_seconds, 2.01);
  EXPECT_EQ(stats.scan_to_cmd_vel.matched, 0);  // no CMD_VEL
  EXPECT_TRUE(std::isnan(stats.scan_to_cmd_vel.median_ms));
}

// Restarts and how each process last ended on its own come from the same statuses; the TERM of
// the shutdown at the end of the log is the deputy's doing and does not overwrite them.
TEST(ComputeLogStats, RestartsAndLastEndsFromTheStatuses) {
  auto with = [](procman_process_status_t p, int restarts, int exit_code, bool should_run = true) {
    p.restarts = restarts;
    p.exit_code = exit_code;
    p.should_run = should_run;
    return p;
  };
  constexpr int8_t kBackoff = procman_process_status_t::STATE_BACKOFF;
  constexpr int8_t kStopped = procman_process_status_t::STATE_STOPPED;
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    log.Write(channels::kProcmanStatus, kStartUs,
              Status("explore", {Process("slam", kRunning, 50.0, 0)}));
    log.Write(channels::kProcmanStatus, kStartUs + 1'000'000,
              Status("explore", {with(Process("slam", kBackoff, 0.0, 0), 0, -9)}));
    log.Write(channels::kProcmanStatus, kStartUs + 2'000'000,
              Status("explore", {with(Process("slam", kRunning, 40.0, 0), 1, -9)}));
    log.Write(channels::kProcmanStatus, kStartUs + 3'000'000,
              Status("explore", {with(Process("slam", kStopped, 0.0, 0), 1, -15, false)}));
  }
  const LogStats stats = ComputeLogStats(log_path);
  ASSERT_EQ(stats.processes.size(), 1u);
  EXPECT_EQ(stats.processes[0].history.restarts, 1);
  EXPECT_EQ(stats.processes[0].history.last_signal, 9);
  const std::string json = LogStatsJson(stats);
  EXPECT_NE(json.find("\"restarts\": 1, \"last_exit_code\": null, \"last_signal\": \"SIGKILL\""),
            std::string::npos)
      << json;
  EXPECT_NE(LogStatsTable(stats).find("SIGKILL"), std::string::npos);
}

// Bytes that are not the channel's type are skipped and counted; channels
// this analysis does not read are not judged.
TEST(ComputeLogStats, UndecodableMessagesAreSkippedAndCounted) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    LcmLogWriter log(log_path);
    log.Write(channels::kLidarScan, kStartUs, Scan(500));
    WriteRawBytes(&log, channels::kCmdVel, kStartUs + 1'000, {1, 2, 3});
    log.Write(channels::kProcmanStatus, kStartUs + 2'000, Command(500));  // the wrong type
    WriteRawBytes(&log, channels::kSlamMap, kStartUs + 3'000, {4, 5});    // not read
    log.Write(channels::kCmdVel, kStartUs + 8'000, Command(500));
    log.Write(channels::kProcmanStatus, kStartUs + 9'000,
              Status("robot", {Process("aslam-nav", kRunning, 12.0, 1024 * 1024)}));
  }
  const LogStats stats = ComputeLogStats(log_path);
  EXPECT_EQ(stats.undecodable, 2);
  EXPECT_EQ(stats.scan_to_cmd_vel.matched, 1);
  EXPECT_EQ(stats.scan_to_cmd_vel.unmatched_commands, 0);
  EXPECT_DOUBLE_EQ(stats.scan_to_cmd_vel.max_ms, 8.0);
  ASSERT_EQ(stats.processes.size(), 1u);
  EXPECT_DOUBLE_EQ(stats.processes[0].mean_cpu_percent, 12.0);
  EXPECT_DOUBLE_EQ(stats.processes[0].share, 1.0);
  // Every channel is counted, decodable or not; the most bytes first.
  ASSERT_EQ(stats.channels.size(), 4u);
  for (std::size_t i = 1; i < stats.channels.size(); ++i) {
    EXPECT_GE(stats.channels[i - 1].bytes, stats.channels[i].bytes);
  }
  const auto traffic_of = [&](const std::string& name) {
    for (const ChannelTraffic& c : stats.channels) {
      if (c.channel == name) return c;
    }
    return ChannelTraffic{};
  };
  EXPECT_EQ(traffic_of(channels::kSlamMap).messages, 1);
  EXPECT_EQ(traffic_of(channels::kSlamMap).bytes, 2);
  EXPECT_EQ(traffic_of(channels::kCmdVel).messages, 2);
  EXPECT_EQ(traffic_of(channels::kCmdVel).largest_bytes,
            static_cast<int64_t>(Command(500).getEncodedSize()));
  EXPECT_EQ(traffic_of(channels::kCmdVel).bytes, 3 + traffic_of(channels::kCmdVel).largest_bytes);
  EXPECT_EQ(traffic_of(channels::kProcmanStatus).messages, 2);
}

void ExpectRuntimeErrorNaming(const std::string& path) {
  try {
    ComputeLogStats(path);
    FAIL() << "expected std::runtime_error for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(ComputeLogStats, MissingFileThrowsNamingIt) {
  ExpectRuntimeErrorNaming(TestTempPath("no_such_dir/run.lcmlog"));
}

TEST(ComputeLogStats, GarbageFileThrowsNamingIt) {
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    std::ofstream out(log_path, std::ios::binary);
    for (int i = 0; i < 1000; ++i) out << "this is not an lcm log\n";
  }
  ExpectRuntimeErrorNaming(log_path);
}

TEST(ComputeLogStats, EmptyFileThrowsNamingIt) {
  const std::string log_path = TestTempPath("run.lcmlog");
  { std::ofstream out(log_path, std::ios::binary); }
  ExpectRuntimeErrorNaming(log_path);
}

// The JSON of hand-made stats, whole: fixed key order, NaN as null.
TEST(LogStatsJson, FixedKeysAndNullForNaN) {
  LogStats stats;
  stats.log_seconds = 12.5;
  stats.undecodable = 3;
  stats.total_mean_cpu_percent = 50.0;
  ProcessCpu slam;
  slam.name = "aslam-slam";
  slam.samples = 4;
  slam.mean_cpu_percent = 37.5;
  slam.max_cpu_percent = 90.0;
  slam.share = 0.75;
  slam.max_rss_mib = 120.25;
  slam.history.restarts = 2;
  slam.history.last_signal = 9;
  ProcessCpu idle;
  idle.name = "aslam-\"idle\"";
  idle.history.last_exit_code = 1;
  stats.processes = {slam, idle};
  stats.scan_to_cmd_vel.matched = 0;
  stats.scan_to_cmd_vel.unmatched_commands = 1;
  stats.channels = {{"SLAM_MAP", 2, 3000, 2000}};
  EXPECT_EQ(
      LogStatsJson(stats),
      "{\n"
      "  \"log_seconds\": 12.5,\n"
      "  \"undecodable\": 3,\n"
      "  \"events\": 0,\n"
      "  \"truncated\": false,\n"
      "  \"read_bytes\": 0,\n"
      "  \"file_bytes\": 0,\n"
      "  \"skipped_bytes\": 0,\n"
      "  \"total_mean_cpu_percent\": 50,\n"
      "  \"processes\": [\n"
      "    {\"name\": \"aslam-slam\", \"samples\": 4, \"mean_cpu_percent\": 37.5, "
      "\"max_cpu_percent\": 90, "
      "\"share\": 0.75, \"max_rss_mib\": 120.25, \"restarts\": 2, \"last_exit_code\": null, "
      "\"last_signal\": \"SIGKILL\"},\n"
      "    {\"name\": \"aslam-\\\"idle\\\"\", \"samples\": 0, \"mean_cpu_percent\": null, "
      "\"max_cpu_percent\": "
      "null, \"share\": null, \"max_rss_mib\": null, \"restarts\": 0, \"last_exit_code\": 1, "
      "\"last_signal\": null}\n"
      "  ],\n"
      "  \"scan_to_cmd_vel\": {\"matched\": 0, \"unmatched_commands\": 1, \"median_ms\": null, "
      "\"p99_ms\": null, \"max_ms\": null},\n"
      "  \"channels\": [\n"
      "    {\"channel\": \"SLAM_MAP\", \"messages\": 2, \"bytes\": 3000, \"largest_bytes\": 2000}\n"
      "  ]\n"
      "}\n");
}

TEST(LogStatsJson, NoProcessesIsAnEmptyArray) {
  const std::string json = LogStatsJson(LogStats{});
  EXPECT_NE(json.find("\"processes\": [],\n"), std::string::npos) << json;
  EXPECT_NE(json.find("\"median_ms\": null"), std::string::npos) << json;
}

TEST(LogStatsTable, RowsInOrderWithDashForMissing) {
  LogStats stats;
  stats.log_seconds = 61.0;
  stats.total_mean_cpu_percent = 50.0;
  ProcessCpu slam;
  slam.name = "aslam-slam";
  slam.samples = 4;
  slam.mean_cpu_percent = 37.5;
  slam.max_cpu_percent = 90.0;
  slam.share = 0.75;
  slam.max_rss_mib = 120.25;
  ProcessCpu nav = slam;
  nav.name = "aslam-nav";
  nav.mean_cpu_percent = 12.5;
  nav.share = 0.25;
  nav.history.restarts = 2;
  nav.history.last_signal = 9;
  stats.processes = {slam, nav};
  stats.scan_to_cmd_vel.matched = 10;
  stats.scan_to_cmd_vel.median_ms = 1.5;
  stats.scan_to_cmd_vel.p99_ms = 4.25;
  stats.scan_to_cmd_vel.max_ms = 7.0;
  stats.channels = {{"SLAM_MAP", 449, 3 * 1024 * 1024, 20 * 1024}, {"CMD_VEL", 10, 400, 40}};
  const std::string table = LogStatsTable(stats);
  EXPECT_EQ(table,
            "process    mean CPU %  max CPU %   share  max RSS MiB restarts last end\n"
            "aslam-slam       37.5       90.0   75.0%        120.2        0        -\n"
            "aslam-nav        12.5       90.0   25.0%        120.2        2  SIGKILL\n"
            "total            50.0\n"
            "LIDAR_SCAN -> CMD_VEL: median 1.50 ms, p99 4.25 ms, max 7.00 ms (10 matched, 0 "
            "unmatched commands)\n"
            "channel   messages       MiB  largest kB\n"
            "SLAM_MAP       449      3.00        20.0\n"
            "CMD_VEL         10      0.00         0.0\n"
            "log: 61.0 s, 0 undecodable messages\n");

  const std::string empty = LogStatsTable(LogStats{});
  EXPECT_NE(empty.find("no PROCMAN_STATUS"), std::string::npos) << empty;
  EXPECT_NE(empty.find("median - ms, p99 - ms, max - ms"), std::string::npos) << empty;
}

// Offsets where the events of an lcm log start, parsed from its bytes (big-endian sync word
// 0xEDA1DA01, event number, timestamp, channel length, data length, channel, data), and the end.
std::vector<int64_t> EventStarts(const std::string& bytes) {
  auto be32 = [&](std::size_t at) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | static_cast<uint8_t>(bytes.at(at + i));
    return static_cast<int64_t>(v);
  };
  std::vector<int64_t> starts;
  std::size_t at = 0;
  while (at < bytes.size()) {
    EXPECT_EQ(be32(at), 0xEDA1DA01) << "no sync word at byte " << at;
    starts.push_back(static_cast<int64_t>(at));
    at += 28 + be32(at + 20) + be32(at + 24);
  }
  EXPECT_EQ(at, bytes.size());
  starts.push_back(static_cast<int64_t>(at));
  return starts;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A recorded fixture cut in the middle of an event: everything before the cut is read and
// reported, and the stats, the table, the JSON and the warning all say where reading stopped.
TEST(ComputeLogStats, TruncatedFixtureIsReadToItsLastWholeEventAndSaysSo) {
  const std::string fixture = std::string(ASLAM_SOURCE_DIR) + "/logs/test_drive.lcmlog";
  const std::string bytes = ReadBytes(fixture);
  const std::vector<int64_t> starts = EventStarts(bytes);
  const int64_t whole_events = static_cast<int64_t>(starts.size()) - 1;
  ASSERT_GT(whole_events, 100);

  const LogStats whole = ComputeLogStats(fixture);
  EXPECT_FALSE(whole.truncated);
  EXPECT_EQ(whole.events, whole_events);
  EXPECT_EQ(whole.read_bytes, static_cast<int64_t>(bytes.size()));
  EXPECT_EQ(whole.file_bytes, static_cast<int64_t>(bytes.size()));
  EXPECT_EQ(whole.skipped_bytes, 0);
  EXPECT_EQ(LogStatsWarning(whole, fixture), "");
  EXPECT_EQ(LogStatsTable(whole).find("TRUNCATED"), std::string::npos);

  // Cut half-way through the event that starts the second half of the log.
  const std::size_t kept_events = static_cast<std::size_t>(whole_events / 2);
  const int64_t stop = starts[kept_events];
  const int64_t cut = stop + (starts[kept_events + 1] - stop) / 2;
  ASSERT_GT(cut, stop);
  const std::string log_path = TestTempPath("run.lcmlog");
  {
    std::ofstream out(log_path, std::ios::binary);
    out.write(bytes.data(), cut);
  }
  const LogStats cut_short = ComputeLogStats(log_path);
  EXPECT_TRUE(cut_short.truncated);
  EXPECT_EQ(cut_short.events, static_cast<int64_t>(kept_events));
  EXPECT_EQ(cut_short.read_bytes, stop);
  EXPECT_EQ(cut_short.file_bytes, cut);
  EXPECT_GT(cut_short.log_seconds, 0.0);
  EXPECT_LT(cut_short.log_seconds, whole.log_seconds);

  const std::string warning = LogStatsWarning(cut_short, log_path);
  EXPECT_NE(warning.find(log_path), std::string::npos) << warning;
  EXPECT_NE(warning.find("stopped at byte " + std::to_string(stop) + " of " + std::to_string(cut)),
            std::string::npos)
      << warning;
  const std::string json = LogStatsJson(cut_short);
  EXPECT_NE(json.find("\"truncated\": true,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"read_bytes\": " + std::to_string(stop) + ","), std::string::npos) << json;
  EXPECT_NE(LogStatsTable(cut_short).find("TRUNCATED"), std::string::npos);
}

// One event of `message` on `channel` at `logged_us`, as the bytes of a log of its own.
template <typename Msg>
std::string EventBytes(const std::string& path, const std::string& channel, int64_t logged_us,
                       const Msg& message) {
  {
    LcmLogWriter log(path);
    log.Write(channel, logged_us, message);
  }
  return ReadBytes(path);
}

// Bytes before the first event are skipped by LCM to the first sync word; the stats count them
// instead of passing over them in silence.
TEST(ComputeLogStats, BytesBeforeTheFirstEventAreCountedAsSkipped) {
  const std::string log_path = TestTempPath("run.lcmlog");
  const std::string scan = EventBytes(log_path, channels::kLidarScan, kStartUs, Scan(500));
  const std::string command =
      EventBytes(log_path, channels::kCmdVel, kStartUs + 4'000, Command(500));
  {
    std::ofstream out(log_path, std::ios::binary);
    out << "torn" << scan << command;
  }
  const LogStats stats = ComputeLogStats(log_path);
  EXPECT_EQ(stats.events, 2);
  EXPECT_FALSE(stats.truncated);
  EXPECT_EQ(stats.skipped_bytes, 4);
  EXPECT_EQ(stats.scan_to_cmd_vel.matched, 1);
  const std::string warning = LogStatsWarning(stats, log_path);
  EXPECT_NE(warning.find(log_path), std::string::npos) << warning;
  EXPECT_NE(warning.find("4 bytes between events"), std::string::npos) << warning;
}

// Bytes that are no event in the middle of a log (a torn write): LCM 1.3 stops reading there
// (and drops the event before them). Whatever the library does, the stats do not hide it.
TEST(ComputeLogStats, GarbageInTheMiddleIsReportedNotHidden) {
  const std::string log_path = TestTempPath("run.lcmlog");
  const std::string a = EventBytes(log_path, channels::kLidarScan, kStartUs, Scan(500));
  const std::string b = EventBytes(log_path, channels::kLidarScan, kStartUs + 1'000, Scan(600));
  const std::string c = EventBytes(log_path, channels::kLidarScan, kStartUs + 2'000, Scan(700));
  {
    std::ofstream out(log_path, std::ios::binary);
    out << a << a << b << "torn" << c;
  }
  const LogStats stats = ComputeLogStats(log_path);
  EXPECT_LT(stats.events, 4);
  EXPECT_TRUE(stats.truncated || stats.skipped_bytes == 4);
  EXPECT_NE(LogStatsWarning(stats, log_path).find(log_path), std::string::npos);
}

}  // namespace
}  // namespace aslam
