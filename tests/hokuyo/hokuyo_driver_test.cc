// The Hokuyo driver against the emulator (written from the SCIP 2.0 document):
// a URG-04LX over a pseudo-terminal and a UST-10LX over loopback TCP.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <fstream>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>

#include "common/test_temp_dir.h"
#include "drivers/emulators/hokuyo_emulator.h"
#include "drivers/hokuyo/hokuyo_driver.h"
#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"
#include "drivers/io/tcp_stream.h"

namespace aslam {
namespace {

using testing::EmulatedHokuyo;
using testing::EmulatedScan;
using testing::HokuyoEmulator;
using testing::HokuyoEmulatorOptions;

constexpr double kTwoPi = 2.0 * M_PI;

// A room-like range function that differs at every angle (so a wrong angle mapping shows).
double RoomRangeM(double angle_rad, int64_t /*scan_index*/) {
  return 1.2 + 0.5 * std::sin(3.0 * angle_rad) + 0.3 * std::cos(angle_rad);
}

bool WaitFor(const std::function<bool()>& condition, double timeout_s = 10.0) {
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::milliseconds(static_cast<int>(timeout_s * 1000));
  while (std::chrono::steady_clock::now() < until) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

HokuyoOptions FastOptions() {
  HokuyoOptions o;
  o.time_sync_round_trips = 5;
  o.response_timeout_s = 0.5;
  o.scan_timeout_s = 0.4;
  o.reconnect_backoff_s = 0.05;
  o.reconnect_backoff_max_s = 0.2;
  return o;
}

// HokuyoDriver::Run on its own thread, collecting scans and log lines.
class RunningDriver {
 public:
  explicit RunningDriver(HokuyoOptions options) : driver_(std::move(options)) {
    driver_.set_log([this](const std::string& line) {
      std::lock_guard<std::mutex> lock(mutex_);
      log_.push_back(line);
    });
    thread_ = std::thread([this] {
      driver_.Run(stop_, [this](const LidarScan& scan) {
        std::lock_guard<std::mutex> lock(mutex_);
        scans_.push_back(scan);
      });
    });
  }
  ~RunningDriver() { Stop(); }
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  std::vector<LidarScan> scans() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_;
  }
  std::size_t num_scans() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_.size();
  }
  std::string log() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string all;
    for (const auto& line : log_) all += line + "\n";
    return all;
  }
  bool WaitForScans(std::size_t more_than, double timeout_s = 10.0) const {
    return WaitFor([&] { return num_scans() > more_than; }, timeout_s);
  }
  HokuyoDriver& driver() { return driver_; }

 private:
  HokuyoDriver driver_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  std::vector<LidarScan> scans_;
  std::vector<std::string> log_;
  std::thread thread_;
};

// The emulator's record of the scan whose beam 0 is nearest `utime`.
const EmulatedScan* Nearest(const std::vector<EmulatedScan>& sent, int64_t utime) {
  const EmulatedScan* best = nullptr;
  for (const auto& s : sent) {
    if (!best ||
        std::llabs(s.beam0_host_utime - utime) < std::llabs(best->beam0_host_utime - utime)) {
      best = &s;
    }
  }
  return best;
}

void ExpectRangesMatch(const LidarScan& scan, const std::function<double(double)>& range_m,
                       double max_mm) {
  ASSERT_EQ(scan.range_m.size(), scan.beam_time_s.size());
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    const double expected = range_m(scan.BeamAngle(i));
    if (expected * 1000.0 < 20.0 || expected * 1000.0 > max_mm) {
      EXPECT_EQ(scan.range_m[i], 0.0f) << "beam " << i;
    } else {
      EXPECT_NEAR(scan.range_m[i], expected, 0.0006) << "beam " << i;
    }
  }
}

// ---- Pure pieces: clock mapping and config ----

TEST(HokuyoClockMapperTest, ShortestRoundTripSetsTheOffset) {
  SensorClockMapper clock;
  // Sensor ms 1000 was read mid-way in [10'000, 10'400] us; a slower trip disagrees by 3 ms.
  clock.Sync({{5'000, 995, 15'000}, {10'000, 1000, 10'400}, {20'000, 1013, 26'000}});
  EXPECT_EQ(clock.offset_us(), 10'200 - 1'000'000);
  EXPECT_EQ(clock.ToHostUtime(1100), 10'200 + 100'000);
  EXPECT_NEAR(clock.best_round_trip_s(), 0.0004, 1e-9);
}

TEST(HokuyoClockMapperTest, UnwrapsThe24BitTimestamp) {
  SensorClockMapper clock;
  const uint32_t near_wrap = (1u << 24) - 50;
  clock.Sync({{0, near_wrap, 0}});
  EXPECT_EQ(clock.ToHostUtime(near_wrap + 40), 40'000);
  EXPECT_EQ(clock.ToHostUtime(10), 60'000);  // wrapped: 16777226 - 16777166 ms
  EXPECT_EQ(clock.ToHostUtime(5), 55'000);   // a little backwards is backwards
  EXPECT_EQ(clock.ToHostUtime(3'000'010), 3'000'060'000);
}

TEST(HokuyoClockMapperTest, SyncAcrossTheWrapHolds) {
  SensorClockMapper clock;
  const uint32_t before = (1u << 24) - 1;
  clock.Sync({{0, before, 2'000}, {10'000, 1, 10'100}});  // 2 ms later on the sensor
  EXPECT_EQ(clock.ToHostUtime(11), 10'050 + 10'000);
}

TEST(HokuyoOptionsTest, LoadsTheSectionAndNamesBadKeys) {
  const HokuyoOptions o = LoadHokuyoOptions(ConfigReader::FromString(
      "hokuyo:\n  host: 10.0.0.5\n  model: ust20lx\n  start_step: 100\n  end_step: 900\n"
      "  two_char_encoding: true\n  reconnect_backoff_s: 0.25\n",
      "hokuyo", "test.yaml"));
  EXPECT_EQ(o.host, "10.0.0.5");
  EXPECT_EQ(o.model, HokuyoModel::kUst20lx);
  EXPECT_EQ(o.start_step, 100);
  EXPECT_EQ(o.end_step, 900);
  EXPECT_TRUE(o.two_char_encoding);
  EXPECT_EQ(o.device_name(), "10.0.0.5:10940");
  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      LoadHokuyoOptions(ConfigReader::FromString(yaml, "hokuyo", "test.yaml"));
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("hokuyo:\n  model: lms100\n").find("model"), std::string::npos);
  EXPECT_NE(error_of("hokuyo:\n  cluster_count: 0\n").find("cluster_count"), std::string::npos);
  EXPECT_NE(error_of("hokuyo:\n  prot: 1\n").find("prot"), std::string::npos);
  EXPECT_NE(error_of("hokuyo:\n  start_step: 500\n  end_step: 100\n").find("end_step"),
            std::string::npos);
}

TEST(HokuyoOptionsTest, TheLidarMountComesFromTheRobotSection) {
  const std::string file = TestTempPath("mount.yaml");
  std::ofstream(file) << "robot:\n  lidar_mount: {x_m: 0.1, y_m: 0.02, yaw_rad: -0.5}\n"
                         "hokuyo:\n  host: 10.0.0.7\n";
  const HokuyoOptions o = LoadHokuyoOptionsFromFile(file);
  EXPECT_EQ(o.host, "10.0.0.7");
  EXPECT_EQ(o.sensor_pose.x_m, 0.1);
  EXPECT_EQ(o.sensor_pose.y_m, 0.02);
  EXPECT_EQ(o.sensor_pose.yaw_rad, -0.5);
}

TEST(HokuyoOptionsTest, TransportDefaultsFollowTheModel) {
  HokuyoOptions urg;
  urg.model = HokuyoModel::kUrg04lx;
  ResolveHokuyoTransport(&urg);
  EXPECT_EQ(urg.port, "/dev/ttyACM0");
  HokuyoOptions ust;
  ust.model = HokuyoModel::kUst10lx;
  ResolveHokuyoTransport(&ust);
  EXPECT_EQ(ust.device_name(), "192.168.0.10:10940");
  HokuyoOptions none;
  EXPECT_THROW(ResolveHokuyoTransport(&none), ConfigError);
  HokuyoOptions both;
  both.port = "/dev/ttyACM0";
  both.host = "192.168.0.10";
  EXPECT_THROW(ResolveHokuyoTransport(&both), ConfigError);
}

// ---- A session over each transport ----

TEST(HokuyoSerialTest, ConnectSendsByteExactCommandsAndReadsTheUrgGeometry) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  SerialPort port(emulator->device_path(), 115200);
  HokuyoOptions o = FastOptions();
  o.port = emulator->device_path();
  HokuyoSession session(port, o);
  const HokuyoInfo& info = session.Connect();
  session.SyncTime();
  session.Start();
  const std::vector<std::string> expected = {"QT\n",  "VV\n",  "PP\n",  "II\n",
                                             "TM0\n", "TM1\n", "TM1\n", "TM1\n",
                                             "TM1\n", "TM1\n", "TM2\n", "MD0044072501000\n"};
  EXPECT_EQ(emulator->received_commands(), expected);
  EXPECT_EQ(info.model, HokuyoModel::kUrg04lx);
  EXPECT_EQ(info.parameters.steps_per_turn, 1024);
  EXPECT_EQ(info.parameters.first_step, 44);
  EXPECT_EQ(info.parameters.last_step, 725);
  EXPECT_EQ(info.parameters.front_step, 384);
  EXPECT_EQ(info.parameters.scan_rpm, 600);
  EXPECT_EQ(info.version.at("PROT"), "SCIP 2.0");
  EXPECT_EQ(info.state.at("STAT"), "Sensor works well.");
  EXPECT_FALSE(info.was_in_scip11);
}

TEST(HokuyoSerialTest, UrgScansMatchTheRangeFunctionAtEachStepAngle) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  e.time_scale = 2.0;
  // No return straight ahead and beyond DMAX on one side: both must come out as 0.
  auto range = [](double angle_rad) {
    if (std::fabs(angle_rad) < 0.05) return 0.0;
    if (angle_rad > 1.9) return 7.0;
    return RoomRangeM(angle_rad, 0);
  };
  e.range_m = [range](double angle_rad, int64_t) { return range(angle_rad); };
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  SerialPort port(emulator->device_path(), 115200);
  HokuyoOptions o = FastOptions();
  HokuyoSession session(port, o);
  session.Connect();
  session.SyncTime();
  session.Start();
  for (int n = 0; n < 3; ++n) {
    const auto scan = session.ReadScan(2000);
    ASSERT_TRUE(scan.has_value());
    ASSERT_EQ(scan->range_m.size(), 682u);  // steps 44..725
    // (44 - 384) steps of 2 pi / 1024, counter-clockwise positive.
    EXPECT_NEAR(scan->angle_min_rad, -340.0 * kTwoPi / 1024.0, 1e-9);
    EXPECT_NEAR(scan->angle_increment_rad, kTwoPi / 1024.0, 1e-12);
    EXPECT_NEAR(scan->BeamAngle(681), 341.0 * kTwoPi / 1024.0, 1e-9);
    EXPECT_DOUBLE_EQ(scan->range_min_m, 0.020);
    EXPECT_DOUBLE_EQ(scan->range_max_m, 5.600);
    ExpectRangesMatch(*scan, range, 5600);
    // 100 ms per turn of 1024 steps: beam i is i * 97.66 us after beam 0.
    EXPECT_FLOAT_EQ(scan->beam_time_s[0], 0.0f);
    EXPECT_NEAR(scan->beam_time_s[1], 0.1 / 1024.0, 1e-7);
    EXPECT_NEAR(scan->beam_time_s[681], 681 * 0.1 / 1024.0, 1e-6);
  }
}

TEST(HokuyoTcpTest, UstScansOverTcpWithByteExactCommandAndGeometry) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  e.range_m = RoomRangeM;
  auto emulator = HokuyoEmulator::OnTcp(e);
  TcpStream stream("127.0.0.1", emulator->tcp_port(), 1000);
  HokuyoOptions o = FastOptions();
  o.host = "127.0.0.1";
  o.tcp_port = emulator->tcp_port();
  o.sensor_pose = {0.15, 0.0, M_PI};  // mounted ahead, looking backwards
  HokuyoSession session(stream, o);
  EXPECT_EQ(session.Connect().model, HokuyoModel::kUst10lx);
  session.SyncTime();
  session.Start();
  EXPECT_EQ(emulator->received_commands().back(), "MD0000108001000\n");
  const auto scan = session.ReadScan(2000);
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->range_m.size(), 1081u);
  EXPECT_NEAR(scan->angle_min_rad, -0.75 * M_PI, 1e-9);  // (0 - 540) of 1440 steps
  EXPECT_NEAR(scan->BeamAngle(1080), 0.75 * M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(scan->range_max_m, 30.0);
  ExpectRangesMatch(
      *scan, [](double a) { return RoomRangeM(a, 0); }, 30000);
  // 25 ms per turn of 1440 steps: the 270 degree sweep takes 18.75 ms.
  EXPECT_NEAR(scan->beam_time_s[1080], 0.01875, 1e-6);
  EXPECT_EQ(scan->sensor_pose.x_m, 0.15);
  EXPECT_EQ(scan->sensor_pose.yaw_rad, M_PI);
}

TEST(HokuyoTcpTest, TwoCharacterMsScans) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  e.range_m = RoomRangeM;  // 0.4 .. 2.0 m: all fit 2 characters
  auto emulator = HokuyoEmulator::OnTcp(e);
  TcpStream stream("127.0.0.1", emulator->tcp_port(), 1000);
  HokuyoOptions o = FastOptions();
  o.two_char_encoding = true;
  o.start_step = 100;
  o.end_step = 980;
  HokuyoSession session(stream, o);
  session.Connect();
  session.SyncTime();
  session.Start();
  EXPECT_EQ(emulator->received_commands().back(), "MS0100098001000\n");
  const auto scan = session.ReadScan(2000);
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->range_m.size(), 881u);
  EXPECT_NEAR(scan->angle_min_rad, (100 - 540) * kTwoPi / 1440, 1e-9);
  EXPECT_NEAR(scan->range_max_m, 4.095, 1e-9);
  ExpectRangesMatch(
      *scan, [](double a) { return RoomRangeM(a, 0); }, 4095);
}

TEST(HokuyoSerialTest, GsPollingWithClusters) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  e.time_scale = 4.0;
  e.range_m = RoomRangeM;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  SerialPort port(emulator->device_path(), 115200);
  HokuyoOptions o = FastOptions();
  o.poll_single_scans = true;
  o.two_char_encoding = true;
  o.cluster_count = 3;
  HokuyoSession session(port, o);
  session.Connect();
  session.SyncTime();
  session.Start();
  for (int n = 0; n < 3; ++n) {
    const auto scan = session.ReadScan(2000);
    ASSERT_TRUE(scan.has_value());
    ASSERT_EQ(scan->range_m.size(), 228u);  // 682 steps in clusters of 3
    EXPECT_NEAR(scan->angle_increment_rad, 3 * kTwoPi / 1024, 1e-12);
    // A cluster's beam points at its middle step and carries its nearest reading.
    for (std::size_t i = 0; i + 1 < scan->range_m.size(); ++i) {
      const int first = 44 + static_cast<int>(i) * 3;
      double nearest = 1e9;
      for (int s = first; s < first + 3; ++s) {
        nearest = std::min(nearest, RoomRangeM((s - 384) * kTwoPi / 1024, 0));
      }
      EXPECT_NEAR(scan->BeamAngle(i), (first + 1 - 384) * kTwoPi / 1024, 1e-9);
      EXPECT_NEAR(scan->range_m[i], nearest, 0.0006) << "beam " << i;
    }
  }
  // BM, then one GS per scan.
  const auto commands = emulator->received_commands();
  const std::vector<std::string> tail(commands.end() - 3, commands.end());
  EXPECT_EQ(tail, std::vector<std::string>(3, "GS0044072503\n"));
  EXPECT_NE(std::find(commands.begin(), commands.end(), "BM\n"), commands.end());
}

TEST(HokuyoTcpTest, GdPolling) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  e.range_m = RoomRangeM;
  auto emulator = HokuyoEmulator::OnTcp(e);
  TcpStream stream("127.0.0.1", emulator->tcp_port(), 1000);
  HokuyoOptions o = FastOptions();
  o.poll_single_scans = true;
  HokuyoSession session(stream, o);
  session.Connect();
  session.SyncTime();
  session.Start();
  const auto scan = session.ReadScan(2000);
  ASSERT_TRUE(scan.has_value());
  EXPECT_EQ(emulator->received_commands().back(), "GD0000108001\n");
  ExpectRangesMatch(
      *scan, [](double a) { return RoomRangeM(a, 0); }, 30000);
}

// ---- Time ----

TEST(HokuyoSerialTest, TimeSyncMapsSensorTimeToHostTime) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  e.time_scale = 2.0;            // a scan every 50 ms: matching by time is unambiguous
  e.clock_start_ms = 9'876'543;  // the sensor clock has nothing to do with the host's
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  HokuyoOptions o = FastOptions();
  o.port = emulator->device_path();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(8));
  const HokuyoStats scanning = running.driver().stats();
  running.Stop();
  const auto sent = emulator->sent_scans();
  for (const LidarScan& scan : running.scans()) {
    const EmulatedScan* match = Nearest(sent, scan.utime);
    ASSERT_NE(match, nullptr);
    // 1 ms timestamp resolution plus the round-trip asymmetry of the best TM1.
    EXPECT_LE(std::llabs(match->beam0_host_utime - scan.utime), 4000) << "seq " << scan.seq;
  }
  // DRIVER_STATUS's figures: the offset is host minus sensor time, the jitter the arrivals'.
  EXPECT_TRUE(scanning.connected);
  EXPECT_FALSE(running.driver().stats().connected);
  const EmulatedScan& first = sent.front();
  EXPECT_NEAR(scanning.clock_offset_ms,
              first.beam0_host_utime * 1e-3 - static_cast<double>(first.timestamp_ms), 4.0);
  EXPECT_GT(scanning.clock_jitter_ms, 0.0);
  EXPECT_LT(scanning.clock_jitter_ms, 10.0);
}

TEST(HokuyoTcpTest, TimestampWrapAt24BitsKeepsTimeMonotonic) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  e.clock_start_ms = (1u << 24) - 600;  // wraps 0.6 s after power-on
  auto emulator = HokuyoEmulator::OnTcp(e);
  HokuyoOptions o = FastOptions();
  o.host = "127.0.0.1";
  o.tcp_port = emulator->tcp_port();
  RunningDriver running(o);
  ASSERT_TRUE(WaitFor([&] {
    const auto sent = emulator->sent_scans();
    return !sent.empty() && sent.back().timestamp_ms < 200'000 && running.num_scans() > 10;
  }));
  ASSERT_TRUE(running.WaitForScans(running.num_scans() + 3));
  running.Stop();
  const auto sent = emulator->sent_scans();
  ASSERT_GT(sent.front().timestamp_ms, (1u << 24) - 1000);  // the stream did cross the wrap
  ASSERT_LT(sent.back().timestamp_ms, 1000u);
  const auto scans = running.scans();
  for (std::size_t i = 0; i < scans.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(scans[i].utime, scans[i - 1].utime) << "scan " << i;
    }
    const EmulatedScan* match = Nearest(sent, scans[i].utime);
    EXPECT_LE(std::llabs(match->beam0_host_utime - scans[i].utime), 4000) << "scan " << i;
  }
}

// ---- Faults ----

TEST(HokuyoTcpTest, ChecksumErrorDropsOneScanNotTheStream) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  auto emulator = HokuyoEmulator::OnTcp(e);
  HokuyoOptions o = FastOptions();
  o.host = "127.0.0.1";
  o.tcp_port = emulator->tcp_port();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(5));
  emulator->CorruptNextScanChecksum();
  ASSERT_TRUE(WaitFor([&] {
    for (const auto& s : emulator->sent_scans()) {
      if (s.corrupted) return true;
    }
    return false;
  }));
  const std::size_t after_corruption = running.num_scans();
  ASSERT_TRUE(running.WaitForScans(after_corruption + 5));
  running.Stop();
  const HokuyoStats stats = running.driver().stats();
  EXPECT_EQ(stats.checksum_errors, 1);
  EXPECT_EQ(stats.reconnects, 0) << running.log();
  EXPECT_EQ(emulator->tcp_connections(), 1);
  // Every scan sent arrived but the corrupted one.
  const auto sent = emulator->sent_scans();
  const auto scans = running.scans();
  for (const auto& s : sent) {
    bool received = false;
    for (const auto& scan : scans) received |= std::llabs(scan.utime - s.beam0_host_utime) < 4000;
    if (s.corrupted) {
      EXPECT_FALSE(received) << "the corrupted scan got through";
    }
  }
  EXPECT_GE(scans.size() + 1, sent.size() - 1);  // at most the one in flight at Stop() missing
}

TEST(HokuyoSerialTest, ErrorStatusAtConnectIsAClearError) {
  HokuyoEmulatorOptions e;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  SerialPort port(emulator->device_path(), 115200);
  HokuyoOptions o = FastOptions();
  emulator->FailNextCommand("PP", "0A");
  HokuyoSession session(port, o);
  try {
    session.Connect();
    FAIL() << "expected ScipSessionError";
  } catch (const ScipSessionError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(emulator->device_path()), std::string::npos) << what;
    EXPECT_NE(what.find("PP answered status 0A"), std::string::npos) << what;
    EXPECT_NE(what.find("unable to create transmission data"), std::string::npos) << what;
  }
  // MD refused: the document's meaning of the status reaches the message.
  HokuyoSession retry(port, o);
  retry.Connect();
  retry.SyncTime();
  emulator->FailNextCommand("MD", "04");
  try {
    retry.Start();
    FAIL() << "expected ScipSessionError";
  } catch (const ScipSessionError& error) {
    EXPECT_NE(std::string(error.what()).find("MD answered status 04 (End Step is out of range)"),
              std::string::npos)
        << error.what();
  }
}

TEST(HokuyoTcpTest, HardwareErrorStatusMidStreamIsReportedAndScanningResumes) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  auto emulator = HokuyoEmulator::OnTcp(e);
  HokuyoOptions o = FastOptions();
  o.host = "127.0.0.1";
  o.tcp_port = emulator->tcp_port();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(3));
  emulator->InjectScanErrorStatus("52");
  ASSERT_TRUE(WaitFor([&] { return running.driver().stats().error_statuses == 1; }));
  const std::size_t after_error = running.num_scans();
  ASSERT_TRUE(running.WaitForScans(after_error + 3)) << running.log();
  running.Stop();
  EXPECT_NE(running.log().find("MD answered status 52 (hardware trouble"), std::string::npos)
      << running.log();
  EXPECT_NE(running.log().find("127.0.0.1:" + std::to_string(emulator->tcp_port())),
            std::string::npos);
}

TEST(HokuyoSerialTest, ResetMidScanRecoversIncludingTheScip11Boot) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  e.time_scale = 2.0;
  e.boot_in_scip11 = true;  // comes back from the reset in SCIP 1.1
  e.range_m = RoomRangeM;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  HokuyoOptions o = FastOptions();
  o.port = emulator->device_path();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(3)) << running.log();
  ASSERT_TRUE(running.driver().info()->was_in_scip11);
  emulator->ResetMidScan();
  ASSERT_TRUE(WaitFor([&] { return running.driver().stats().partial_packets >= 1; }))
      << running.log();
  const std::size_t after_reset = running.num_scans();
  ASSERT_TRUE(running.WaitForScans(after_reset + 5)) << running.log();
  running.Stop();
  const auto commands = emulator->received_commands();
  EXPECT_EQ(std::count(commands.begin(), commands.end(), "SCIP2.0\n"), 2);
  // After the reboot the sensor clock restarted from 0: the re-sync keeps the stamps right.
  const auto sent = emulator->sent_scans();
  const auto scans = running.scans();
  for (std::size_t i = after_reset; i < scans.size(); ++i) {
    EXPECT_LE(std::llabs(Nearest(sent, scans[i].utime)->beam0_host_utime - scans[i].utime), 4000);
    ExpectRangesMatch(
        scans[i], [](double a) { return RoomRangeM(a, 0); }, 5600);
  }
}

TEST(HokuyoSerialTest, UnplugAndReplugResumeScans) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUrg04lx;
  e.time_scale = 2.0;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  // The driver opens a stable name (like /dev/serial/by-id/...) that the test re-points.
  const std::filesystem::path link = TestTempPath("urg");
  std::filesystem::create_symlink(emulator->device_path(), link);
  HokuyoOptions o = FastOptions();
  o.port = link.string();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(3)) << running.log();
  emulator->Unplug();
  ASSERT_TRUE(WaitFor([&] {
    return running.driver().last_error().find("gone") != std::string::npos;
  })) << running.log();
  EXPECT_NE(running.driver().last_error().find(link.string()), std::string::npos);
  const std::size_t while_unplugged = running.num_scans();
  const std::filesystem::path new_link = TestTempPath("urg.new");
  std::filesystem::create_symlink(emulator->Replug(), new_link);
  std::filesystem::rename(new_link, link);  // atomic re-point, as udev does
  ASSERT_TRUE(running.WaitForScans(while_unplugged + 3)) << running.log();
  running.Stop();
  EXPECT_GE(running.driver().stats().reconnects, 1);
}

TEST(HokuyoTcpTest, DisconnectAndReconnectResumeScans) {
  HokuyoEmulatorOptions e;
  e.model = EmulatedHokuyo::kUst10lx;
  auto emulator = HokuyoEmulator::OnTcp(e);
  HokuyoOptions o = FastOptions();
  o.host = "127.0.0.1";
  o.tcp_port = emulator->tcp_port();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(3));
  emulator->Unplug();
  ASSERT_TRUE(WaitFor([&] { return emulator->tcp_connections() == 2; })) << running.log();
  const std::size_t after = running.num_scans();
  ASSERT_TRUE(running.WaitForScans(after + 3)) << running.log();
  running.Stop();
  EXPECT_NE(running.log().find("closed the connection"), std::string::npos) << running.log();
  // The sequence numbers go on across the reconnect.
  const auto scans = running.scans();
  for (std::size_t i = 0; i < scans.size(); ++i) EXPECT_EQ(scans[i].seq, static_cast<int64_t>(i));
}

TEST(HokuyoSerialTest, GarbageBetweenScansIsSkipped) {
  HokuyoEmulatorOptions e;
  e.time_scale = 2.0;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  HokuyoOptions o = FastOptions();
  o.port = emulator->device_path();
  RunningDriver running(o);
  ASSERT_TRUE(running.WaitForScans(3));
  emulator->InjectGarbage("\x13\x80 line noise\n\xff\xfe");
  ASSERT_TRUE(WaitFor([&] { return running.driver().stats().garbage_bytes > 0; }));
  const std::size_t after = running.num_scans();
  ASSERT_TRUE(running.WaitForScans(after + 3));
  running.Stop();
  EXPECT_EQ(running.driver().stats().reconnects, 0) << running.log();
}

TEST(HokuyoSerialTest, GarbageOnlyDeviceGivesAClearErrorNotAHang) {
  HokuyoEmulatorOptions e;
  auto emulator = HokuyoEmulator::OnPseudoTerminal(e);
  emulator->SetGarbageOnly(true);
  SerialPort port(emulator->device_path(), 115200);
  HokuyoOptions o = FastOptions();
  HokuyoSession session(port, o);
  try {
    session.Connect();
    FAIL() << "expected ScipSessionError";
  } catch (const ScipSessionError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(emulator->device_path()), std::string::npos) << what;
    EXPECT_NE(what.find("not in SCIP 2.0"), std::string::npos) << what;
    EXPECT_NE(what.find("baud"), std::string::npos) << what;
  }
  // The driver keeps trying with backoff, returns when stopped and never publishes.
  o.port = emulator->device_path();
  RunningDriver running(o);
  ASSERT_TRUE(WaitFor([&] { return running.driver().stats().reconnects >= 2; }));
  running.Stop();
  EXPECT_EQ(running.num_scans(), 0u);
  EXPECT_NE(running.log().find("not in SCIP 2.0"), std::string::npos) << running.log();
}

TEST(HokuyoDeviceErrorTest, MissingPortAndRefusedTcpNameTheDevice) {
  HokuyoOptions serial = FastOptions();
  serial.port = "/dev/aslam-no-such-hokuyo";
  {
    RunningDriver running(serial);
    ASSERT_TRUE(WaitFor([&] { return !running.driver().last_error().empty(); }));
    EXPECT_NE(running.driver().last_error().find("/dev/aslam-no-such-hokuyo: no such device"),
              std::string::npos)
        << running.driver().last_error();
  }
  // A loopback port nobody listens on: bound, never listened.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  socklen_t length = sizeof(address);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  HokuyoOptions tcp = FastOptions();
  tcp.host = "127.0.0.1";
  tcp.tcp_port = ntohs(address.sin_port);
  {
    RunningDriver running(tcp);
    ASSERT_TRUE(WaitFor([&] { return !running.driver().last_error().empty(); }));
    EXPECT_NE(running.driver().last_error().find("refused"), std::string::npos)
        << running.driver().last_error();
  }
  ::close(fd);
}

}  // namespace
}  // namespace aslam
