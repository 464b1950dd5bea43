// The Kobuki driver against a Kobuki emulated on a pseudo-terminal from the protocol
// specification: byte-exact packets, odometry that follows the base across encoder wraps,
// checksum errors and garbage, the safety stops, clear errors, and unplug/replug.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "drivers/emulators/kobuki_emulator.h"
#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"
#include "drivers/kobuki/kobuki_driver.h"

namespace aslam {
namespace {

using Bytes = std::vector<uint8_t>;

VelocityCommand Command(double linear, double angular) {
  VelocityCommand c;
  c.linear_mps = linear;
  c.angular_radps = angular;
  return c;
}

// A driver connected to an emulator's port, and its log.
class Connected {
 public:
  explicit Connected(KobukiEmulator& emulator, KobukiOptions options = {})
      : port_(emulator.link_path(), 115200),
        driver_(std::move(options), [this](const std::string& line) { log_.push_back(line); }) {
    driver_.Connect(port_);
  }
  // Polls for `seconds`, sending `command` every 100 ms when given; returns the odometry.
  std::vector<Odometry> Drive(double seconds, std::optional<VelocityCommand> command,
                              int* changes = nullptr) {
    std::vector<Odometry> odometry;
    const int64_t end = HostClockUtime() + static_cast<int64_t>(seconds * 1e6);
    int64_t next_command = 0;
    while (HostClockUtime() < end) {
      if (command && HostClockUtime() >= next_command) {
        driver_.OnCommand(*command, HostClockUtime());
        next_command = HostClockUtime() + 100000;
      }
      const bool changed = driver_.Poll(10, &odometry);
      if (changes != nullptr && changed) ++*changes;
    }
    return odometry;
  }
  KobukiDriver& driver() { return driver_; }
  const std::vector<std::string>& log() const { return log_; }

 private:
  std::vector<std::string> log_;
  SerialPort port_;
  KobukiDriver driver_;
};

void ExpectOdometryFollowsTheTruth(const Odometry& odometry, const KobukiTruth& truth,
                                   double tolerance_m) {
  EXPECT_NEAR(odometry.pose.x_m, truth.x_m, tolerance_m);
  EXPECT_NEAR(odometry.pose.y_m, truth.y_m, tolerance_m);
  EXPECT_NEAR(std::remainder(odometry.pose.yaw_rad - truth.yaw_rad, 2 * M_PI), 0.0, 0.01);
}

std::size_t Find(const Bytes& haystack, const Bytes& needle) {
  return std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end()) -
         haystack.begin();
}

TEST(KobukiDriver, ConnectsAsksForItsIdentityAndOdometryFollowsTheBase) {
  KobukiEmulatorOptions options;
  options.initial_left_encoder = 1000;
  options.initial_right_encoder = 40000;
  options.initial_gyro_deg = 33.0;
  options.initial_timestamp_ms = 61000;  // wraps during the test
  KobukiEmulator emulator(options);
  Connected kobuki(emulator);
  // Request Extra for hardware version, firmware version and unique id (0x0B) comes first.
  const Bytes request_extra = {0xAA, 0x55, 0x04, 0x09, 0x02, 0x0B, 0x00, 0x04};
  kobuki.Drive(0.05, std::nullopt);
  const Bytes first = emulator.ReceivedBytes();
  ASSERT_GE(first.size(), request_extra.size());
  EXPECT_EQ(Bytes(first.begin(), first.begin() + 8), request_extra);

  std::vector<Odometry> odometry = kobuki.Drive(1.0, Command(0.25, 0.0));
  const auto more = kobuki.Drive(1.2, Command(0.1, 0.8));
  odometry.insert(odometry.end(), more.begin(), more.end());
  kobuki.Drive(1.0, Command(0.0, 0.0));
  const auto still = kobuki.Drive(0.1, std::nullopt);
  ASSERT_FALSE(still.empty());
  ExpectOdometryFollowsTheTruth(still.back(), emulator.Truth(), 0.01);
  EXPECT_GT(emulator.Truth().x_m, 0.3);
  EXPECT_GT(emulator.Truth().yaw_rad, 0.5);

  // One odometry per feedback packet, 20 ms apart on the base's clock, in time order.
  ASSERT_GT(odometry.size(), 80u);
  for (std::size_t i = 1; i < odometry.size(); ++i) {
    EXPECT_GT(odometry[i].utime, odometry[i - 1].utime);
    EXPECT_NEAR((odometry[i].utime - odometry[i - 1].utime) * 1e-3, 20.0, 15.0);
  }
  const KobukiStatus status = kobuki.driver().status();
  EXPECT_EQ(status.hardware_version, "1.0.4");
  EXPECT_EQ(status.firmware_version, "1.2.0");
  EXPECT_EQ(status.unique_id, "12345678-9ABCDEF0-0BADF00D");
  EXPECT_EQ(status.checksum_errors, 0);
  EXPECT_EQ(emulator.bad_packets_received(), 0);
  const DriverStatus driver = kobuki.driver().driver_status();
  EXPECT_NEAR(driver.rate_hz, 50.0, 5.0);
  EXPECT_GE(driver.clock_jitter_ms, 0.0);
}

TEST(KobukiDriver, BaseControlIsTheSpecsSpeedAndRadiusByteForByte) {
  KobukiEmulator emulator;
  Connected kobuki(emulator);
  kobuki.Drive(0.8, Command(0.2, 0.5));  // past the acceleration ramps
  // An arc of 0.2 / 0.5 = 400 mm (0x0190) at the outer wheel's 0.2 * (400 + 115) / 400 m/s
  // = 257.5 -> 258 mm/s (0x0102); checksum 0x06^0x01^0x04^0x02^0x01^0x90^0x01.
  const Bytes arc = {0xAA, 0x55, 0x06, 0x01, 0x04, 0x02, 0x01, 0x90, 0x01, 0x91};
  EXPECT_LT(Find(emulator.ReceivedBytes(), arc), emulator.ReceivedBytes().size());
  const auto controls = emulator.ReceivedBaseControls();
  ASSERT_FALSE(controls.empty());
  EXPECT_EQ(controls.back().speed_mm_s, 258);
  EXPECT_EQ(controls.back().radius_mm, 400);
  // Turning in place: w * b / 2 = 1.0 * 115 mm/s with radius 1.
  kobuki.Drive(1.0, Command(0.0, 1.0));
  EXPECT_EQ(emulator.ReceivedBaseControls().back().speed_mm_s, 115);
  EXPECT_EQ(emulator.ReceivedBaseControls().back().radius_mm, 1);
}

TEST(KobukiDriver, ChecksumErrorsGarbageAndSplitPacketsCostOnlyTheBadPackets) {
  KobukiEmulator emulator;
  Connected kobuki(emulator);
  kobuki.Drive(0.3, Command(0.2, 0.3));
  emulator.CorruptNextFeedback();
  kobuki.Drive(0.1, Command(0.2, 0.3));
  emulator.InjectGarbage({0x00, 0x13, 0x55, 0xFE, 0xAA, 0x01, 0x02});
  kobuki.Drive(0.1, Command(0.2, 0.3));
  emulator.SplitNextFeedback();
  kobuki.Drive(0.1, Command(0.2, 0.3));
  emulator.CorruptNextFeedback();
  kobuki.Drive(0.5, Command(0.2, 0.3));
  kobuki.Drive(0.6, Command(0.0, 0.0));
  const auto still = kobuki.Drive(0.1, std::nullopt);
  ASSERT_FALSE(still.empty());
  // A lost packet loses no motion: the encoders are counters.
  ExpectOdometryFollowsTheTruth(still.back(), emulator.Truth(), 0.01);
  const KobukiStatus status = kobuki.driver().status();
  EXPECT_GE(status.checksum_errors, 2);
  EXPECT_GE(status.discarded_bytes, 7);
}

TEST(KobukiDriver, EncodersWrapForwardAndBackwardWithoutAJump) {
  KobukiEmulatorOptions options;
  options.initial_left_encoder = 65000;
  options.initial_right_encoder = 64000;
  KobukiEmulator emulator(options);
  Connected kobuki(emulator);
  // 0.3 m/s for 1.3 s is about 4000 ticks: both counters pass 65535.
  std::vector<Odometry> odometry = kobuki.Drive(1.3, Command(0.3, 0.0));
  kobuki.Drive(0.6, Command(0.0, 0.0));
  ExpectOdometryFollowsTheTruth(kobuki.Drive(0.1, std::nullopt).back(), emulator.Truth(), 0.01);
  for (std::size_t i = 1; i < odometry.size(); ++i) {
    EXPECT_LT(std::hypot(odometry[i].pose.x_m - odometry[i - 1].pose.x_m,
                         odometry[i].pose.y_m - odometry[i - 1].pose.y_m),
              0.02);
  }
  // Back again across the wrap.
  kobuki.Drive(1.6, Command(-0.3, 0.0));
  kobuki.Drive(0.6, Command(0.0, 0.0));
  const auto back = kobuki.Drive(0.1, std::nullopt);
  ExpectOdometryFollowsTheTruth(back.back(), emulator.Truth(), 0.01);
  EXPECT_LT(emulator.Truth().x_m, 0.0);
}

TEST(KobukiDriver, ABumperHitStopsTheBaseUntilReleasedAndCommandedAgain) {
  KobukiEmulator emulator;
  Connected kobuki(emulator);
  kobuki.Drive(0.6, Command(0.3, 0.0));
  ASSERT_GT(emulator.Truth().left_wheel_mps, 0.25);
  emulator.SetBumper(0x02);
  int changes = 0;
  kobuki.Drive(0.1, Command(0.3, 0.0), &changes);
  // Stopped within a few packets, with no deceleration ramp, and said so.
  double left = 1, right = 1;
  emulator.CommandedWheelSpeeds(&left, &right);
  EXPECT_EQ(left, 0.0);
  EXPECT_EQ(right, 0.0);
  EXPECT_GE(changes, 1);
  EXPECT_TRUE(kobuki.driver().status().hazard_stop);
  // Commands keep coming while the bumper is pressed: the base stays put.
  const double x_stopped = emulator.Truth().x_m;
  kobuki.Drive(0.5, Command(0.3, 0.0));
  EXPECT_NEAR(emulator.Truth().x_m, x_stopped, 1e-6);
  EXPECT_EQ(kobuki.driver().status().sensors.bumper, 0x02);
  // Released: the next command after the release drives it again.
  emulator.SetBumper(0);
  kobuki.Drive(0.6, Command(0.3, 0.0));
  EXPECT_FALSE(kobuki.driver().status().hazard_stop);
  EXPECT_GT(emulator.Truth().x_m, x_stopped + 0.02);
  // A cliff and a dropped wheel stop it too.
  for (int hazard = 0; hazard < 2; ++hazard) {
    (hazard == 0 ? emulator.SetCliff(0x04) : emulator.SetWheelDrop(0x01));
    kobuki.Drive(0.1, Command(0.3, 0.0));
    emulator.CommandedWheelSpeeds(&left, &right);
    EXPECT_EQ(left, 0.0) << hazard;
    EXPECT_TRUE(kobuki.driver().status().hazard_stop) << hazard;
    (hazard == 0 ? emulator.SetCliff(0) : emulator.SetWheelDrop(0));
    kobuki.Drive(0.3, Command(0.3, 0.0));
  }
}

TEST(KobukiDriver, AStaleCommandStopsTheBase) {
  KobukiEmulator emulator;
  Connected kobuki(emulator);
  kobuki.driver().OnCommand(Command(0.2, 0.0), HostClockUtime());
  kobuki.Drive(0.4, std::nullopt);
  double left = 0, right = 0;
  emulator.CommandedWheelSpeeds(&left, &right);
  EXPECT_GT(left, 0.15);
  EXPECT_FALSE(kobuki.driver().status().command_timeout);
  kobuki.Drive(0.5, std::nullopt);  // 0.9 s after the command: 0.5 s, then 0.2 s of ramp
  emulator.CommandedWheelSpeeds(&left, &right);
  EXPECT_EQ(left, 0.0);
  EXPECT_EQ(right, 0.0);
  EXPECT_TRUE(kobuki.driver().status().command_timeout);
}

TEST(KobukiDriver, SilenceAWrongBaudAndAMissingPortGiveClearErrors) {
  {
    KobukiEmulator emulator;
    KobukiOptions options;
    options.response_timeout_s = 0.3;
    Connected kobuki(emulator, options);
    kobuki.Drive(0.1, std::nullopt);
    emulator.SetSilent(true);
    try {
      kobuki.Drive(1.0, std::nullopt);
      FAIL() << "a silent base was not noticed";
    } catch (const DeviceError& e) {
      EXPECT_NE(std::string(e.what()).find("no feedback"), std::string::npos) << e.what();
    }
  }
  {
    KobukiEmulatorOptions garbled;
    garbled.wrong_baud = true;
    KobukiEmulator emulator(garbled);
    SerialPort port(emulator.link_path(), 115200);
    KobukiOptions options;
    options.response_timeout_s = 0.5;
    KobukiDriver driver(options, [](const std::string&) {});
    try {
      driver.Connect(port);
      FAIL() << "garbage was taken for a Kobuki";
    } catch (const DeviceError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(emulator.link_path()), std::string::npos) << what;
      EXPECT_NE(what.find("none a valid packet"), std::string::npos) << what;
      EXPECT_NE(what.find("115200"), std::string::npos) << what;
    }
  }
  try {
    SerialPort port("/dev/aslam-no-such-kobuki", 115200);
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/aslam-no-such-kobuki"), std::string::npos);
  }
}

TEST(KobukiLoop, UnplugAndReplugReconnectAndOdometryRunsOn) {
  KobukiEmulator emulator;
  KobukiOptions options;
  options.port = emulator.link_path();
  options.response_timeout_s = 0.3;
  options.reconnect_backoff_initial_s = 0.05;
  options.reconnect_backoff_max_s = 0.2;
  KobukiDriver driver(options, [](const std::string&) {});
  std::atomic<bool> stop{false};
  std::vector<Odometry> odometry;
  std::vector<KobukiStatus> statuses;
  KobukiLoopCallbacks callbacks;
  VelocityCommand command = Command(0.2, 0.0);
  std::mutex mutex;
  callbacks.service = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    driver.OnCommand(command, HostClockUtime());
  };
  callbacks.on_odometry = [&](const Odometry& o) {
    std::lock_guard<std::mutex> lock(mutex);
    odometry.push_back(o);
  };
  callbacks.on_status = [&](const KobukiStatus& s, const DriverStatus&) {
    std::lock_guard<std::mutex> lock(mutex);
    statuses.push_back(s);
  };
  std::thread loop([&] { RunKobukiLoop(driver, options, stop, callbacks, [](auto&) {}); });
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  emulator.Unplug();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  emulator.Replug();
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  {
    std::lock_guard<std::mutex> lock(mutex);
    command = Command(0.0, 0.0);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  stop = true;
  loop.join();

  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_GT(odometry.size(), 40u);
  // The motion while unplugged (the base kept its last command) is counted, not lost.
  ExpectOdometryFollowsTheTruth(odometry.back(), emulator.Truth(), 0.02);
  EXPECT_GT(emulator.Truth().x_m, 0.2);
  bool disconnected_seen = false;
  for (std::size_t i = 0; i + 1 < statuses.size(); ++i) disconnected_seen |= !statuses[i].connected;
  EXPECT_TRUE(disconnected_seen);
  EXPECT_GE(statuses.back().reconnects, 1);
  for (std::size_t i = 1; i < odometry.size(); ++i) {
    EXPECT_GT(odometry[i].utime, odometry[i - 1].utime);
  }
}

}  // namespace
}  // namespace aslam
