// The RPLIDAR driver against the emulator (drivers/emulators/rplidar_emulator.h) over a
// pseudo-terminal: the bytes it sends, the scans it makes, and its recovery from faults.
// Every wait is bounded; nothing asserts on wall-clock speed.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/config.h"
#include "common/test_temp_dir.h"
#include "drivers/emulators/rplidar_emulator.h"
#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"
#include "drivers/rplidar/rplidar_driver.h"

namespace aslam {
namespace {

using Bytes = std::vector<uint8_t>;

// Ranges seen by the emulated device in a still room, by angle clockwise from its front.
double Smooth(double angle_cw_rad, int64_t) {  // slope <= 1.1 m/rad
  return 1.5 + 0.5 * std::sin(angle_cw_rad) + 0.3 * std::cos(2.0 * angle_cw_rad);
}
double Wavy(double angle_cw_rad, int64_t) {  // slope <= 2.4 m/rad: a wrong angle shows
  return 2.0 + 0.4 * std::sin(6.0 * angle_cw_rad);
}

double Far(double angle_cw_rad, int64_t) {  // 1 to 20 m: every band of the ultra cabins' scale
  return 10.5 + 9.5 * std::sin(angle_cw_rad);
}

bool EndsWith(const Bytes& bytes, const Bytes& tail) {
  return bytes.size() >= tail.size() &&
         std::equal(tail.begin(), tail.end(), bytes.end() - tail.size());
}

RplidarOptions TestOptions(const std::string& port) {
  RplidarOptions o;
  o.port = port;
  o.response_timeout_s = 0.5;
  o.reset_wait_s = 0.2;
  o.stall_timeout_s = 1.0;
  o.reconnect_backoff_initial_s = 0.05;
  o.reconnect_backoff_max_s = 0.2;
  return o;
}

bool WaitFor(const std::function<bool()>& done, double limit_s) {
  const int64_t deadline = HostClockUtime() + static_cast<int64_t>(limit_s * 1e6);
  while (!done()) {
    if (HostClockUtime() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

bool Contains(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

// An emulator and the driver on its pseudo-terminal.
struct Rig {
  Rig(RplidarEmulatorOptions emulator_options, const std::string& scan_mode = "auto",
      int baud = 115200)
      : emulator(std::move(emulator_options)),
        port(emulator.link_path(), baud),
        options(WithMode(TestOptions(emulator.link_path()), scan_mode)),
        driver(
            port, options, baud, [this](bool asserted) { return port.SetDtr(asserted); },
            [this](const std::string& line) { log.push_back(line); }) {}

  static RplidarOptions WithMode(RplidarOptions o, const std::string& mode) {
    o.scan_mode = mode;
    return o;
  }

  // Polls until `count` more scans arrived (at most limit_s).
  std::vector<LidarScan> Collect(std::size_t count, double limit_s = 10.0) {
    std::vector<LidarScan> scans;
    const int64_t deadline = HostClockUtime() + static_cast<int64_t>(limit_s * 1e6);
    while (scans.size() < count && HostClockUtime() < deadline) driver.Poll(20, &scans);
    // One poll may complete several scans when this thread ran late (a loaded machine).
    if (scans.size() > count) scans.resize(count);
    return scans;
  }

  RplidarEmulator emulator;
  SerialPort port;
  RplidarOptions options;
  std::vector<std::string> log;
  RplidarDriver driver;
};

// Each beam with a return matches the device's range at that beam's angle.
void ExpectRangesMatch(const LidarScan& scan, double (*range_m)(double, int64_t),
                       double tolerance_m, double min_filled_fraction) {
  ASSERT_FALSE(scan.range_m.empty());
  EXPECT_DOUBLE_EQ(scan.angle_min_rad, -M_PI);
  EXPECT_NEAR(scan.angle_increment_rad * scan.range_m.size(), 2.0 * M_PI, 1e-9);
  std::size_t filled = 0;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    if (scan.range_m[i] <= 0.0f) continue;
    ++filled;
    // REP-103: the beam's counter-clockwise angle is the device's clockwise angle negated.
    const double device_angle_cw_rad = -scan.BeamAngle(i);
    ASSERT_NEAR(scan.range_m[i], range_m(device_angle_cw_rad, 0), tolerance_m)
        << "beam " << i << " at " << scan.BeamAngle(i) << " rad";
  }
  EXPECT_GE(filled, min_filled_fraction * scan.range_m.size());
}

// Beam times follow the clockwise sweep at the device's rotation rate.
void ExpectBeamTimesFollowTheSweep(const LidarScan& scan, double rotation_hz) {
  ASSERT_EQ(scan.beam_time_s.size(), scan.range_m.size());
  const double revolution_s = 1.0 / rotation_hz;
  // The earliest beam marks where the sweep started.
  const auto earliest = std::min_element(scan.beam_time_s.begin(), scan.beam_time_s.end());
  EXPECT_GE(*earliest, 0.0f);
  const double start_cw_deg = -scan.BeamAngle(earliest - scan.beam_time_s.begin()) * 180.0 / M_PI;
  int checked = 0;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    const double swept_deg =
        std::fmod(-scan.BeamAngle(i) * 180.0 / M_PI - start_cw_deg + 720.0, 360.0);
    if (swept_deg < 10.0 || swept_deg > 350.0) continue;  // the seam of the revolution
    EXPECT_NEAR(scan.beam_time_s[i], swept_deg / 360.0 * revolution_s, 0.03 * revolution_s)
        << "beam " << i;
    ++checked;
  }
  EXPECT_GT(checked, static_cast<int>(scan.range_m.size() / 2));
}

TEST(RplidarDriver, StandardScanSendsTheDocumentedBytesAndMakesRevolutions) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Smooth;
  Rig rig(device, "standard");
  rig.driver.Start();
  const int64_t start_utime = HostClockUtime();
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  // STOP, GET_INFO, GET_HEALTH, GET_SAMPLERATE, SCAN; the A1 motor goes by DTR, not bytes.
  EXPECT_EQ(rig.emulator.ReceivedBytes(),
            (Bytes{0xA5, 0x25, 0xA5, 0x50, 0xA5, 0x52, 0xA5, 0x59, 0xA5, 0x20}));
  const RplidarConnection& c = rig.driver.connection();
  EXPECT_EQ(c.model, rplidar::Model::kA1);
  EXPECT_EQ(c.format, rplidar::PacketFormat::kStandardNodes);
  EXPECT_DOUBLE_EQ(c.sample_period_s, 508e-6);
  EXPECT_EQ(c.beams_per_revolution, 360);  // 1 / (508 us * 5.5 Hz) = 358 -> 360
  for (const LidarScan& scan : scans) {
    ExpectRangesMatch(scan, Smooth, 0.03, 0.95);
    ExpectBeamTimesFollowTheSweep(scan, 5.5);
    EXPECT_EQ(scan.range_min_m, 0.15);
    EXPECT_EQ(scan.range_max_m, 12.0);
    EXPECT_GE(scan.utime, start_utime - 1000000);
    EXPECT_LE(scan.utime, HostClockUtime());
  }
  EXPECT_EQ(scans[1].seq, scans[0].seq + 1);
  EXPECT_LT(scans[0].utime, scans[1].utime);
  EXPECT_EQ(rig.driver.stats().checksum_errors, 0);
}

TEST(RplidarDriver, DriverStatusReportsRateAndTheSampleClocksJitter) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a2");
  device.range_m = Smooth;
  Rig rig(device, "express");
  rig.driver.Start();
  const std::vector<LidarScan> scans = rig.Collect(25);  // 2.5 s at 10 Hz
  ASSERT_EQ(scans.size(), 25u);
  const DriverStatus status = rig.driver.driver_status();
  EXPECT_EQ(status.driver, "aslam-rplidar");
  EXPECT_EQ(status.device, rig.emulator.link_path());
  EXPECT_TRUE(status.connected);
  EXPECT_EQ(status.messages, rig.driver.stats().revolutions);
  EXPECT_NEAR(status.rate_hz, 10.0, 1.5);
  // The samples' own clock maps onto the host's within a few milliseconds: what a pseudo-
  // terminal and a loaded machine add. A wrong sample period would drift by 10 % (25 ms/rev).
  EXPECT_GE(status.clock_jitter_ms, 0.0);
  EXPECT_LT(status.clock_jitter_ms, 5.0);
  EXPECT_EQ(status.errors, 0);
}

TEST(RplidarDriver, LegacyExpressScanUndoesTheAngleCompensation) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Wavy;
  Rig rig(device, "express");
  rig.driver.Start();
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_EQ(rig.emulator.ReceivedBytes(),
            (Bytes{0xA5, 0x25, 0xA5, 0x50, 0xA5, 0x52, 0xA5, 0x59,  //
                   0xA5, 0x82, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x22}));
  EXPECT_EQ(rig.driver.connection().format, rplidar::PacketFormat::kLegacyCapsules);
  EXPECT_EQ(rig.driver.connection().beams_per_revolution, 720);
  for (const LidarScan& scan : scans) {
    // Half a beam (0.25 deg) off at most, at 2.4 m/rad: 0.011 m, plus quantisation.
    ExpectRangesMatch(scan, Wavy, 0.02, 0.9);
    ExpectBeamTimesFollowTheSweep(scan, 5.5);
  }
}

TEST(RplidarDriver, DenseExpressScanOnAnS1) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("s1");
  device.range_m = Wavy;
  Rig rig(device, "auto", 256000);
  rig.driver.Start();
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  // The S1 motor is commanded: MOTOR_SPEED_CTRL 600 rpm, then EXPRESS_SCAN in mode 1.
  EXPECT_EQ(rig.emulator.ReceivedBytes(),
            (Bytes{0xA5, 0x25, 0xA5, 0x50, 0xA5, 0x52, 0xA5, 0x59, 0xA5, 0xA8, 0x02, 0x58,
                   0x02, 0x55, 0xA5, 0x82, 0x05, 0x01, 0x00, 0x00, 0x00, 0x00, 0x23}));
  const RplidarConnection& c = rig.driver.connection();
  EXPECT_EQ(c.model, rplidar::Model::kS1);
  EXPECT_EQ(c.format, rplidar::PacketFormat::kDenseCapsules);
  EXPECT_EQ(c.beams_per_revolution, 930);  // 1 / (108 us * 10 Hz) = 926 -> 930
  for (const LidarScan& scan : scans) {
    ExpectRangesMatch(scan, Wavy, 0.02, 0.95);
    ExpectBeamTimesFollowTheSweep(scan, 10.0);
    EXPECT_EQ(scan.range_max_m, 40.0);
  }
}

TEST(RplidarDriver, EveryModelScansInItsDefaultMode) {
  struct Case {
    const char* model;
    rplidar::PacketFormat format;
    int beams;  // samples per revolution at the nominal rate, to the nearest ten
  };
  const Case cases[] = {
      {"a2", rplidar::PacketFormat::kLegacyCapsules,
       400},  // 250 us, 10 Hz
              // The A3 lists its modes: Sensitivity, its typical, at 62.5 us, 10 Hz.
      {"a3", rplidar::PacketFormat::kUltraCapsules, 1600},
      {"s2", rplidar::PacketFormat::kDenseCapsules, 3230}};  // 31 us, 10 Hz
  for (const Case& c : cases) {
    SCOPED_TRACE(c.model);
    RplidarEmulatorOptions device = RplidarEmulatorModel(c.model);
    device.range_m = Smooth;
    Rig rig(device);
    rig.driver.Start();
    const std::vector<LidarScan> scans = rig.Collect(2);
    ASSERT_EQ(scans.size(), 2u);
    EXPECT_EQ(rplidar::ModelName(rig.driver.connection().model), std::string(c.model));
    EXPECT_EQ(rig.driver.connection().format, c.format);
    EXPECT_EQ(rig.driver.connection().beams_per_revolution, c.beams);
    for (const LidarScan& scan : scans) {
      ExpectRangesMatch(scan, Smooth, 0.03, 0.9);
      ExpectBeamTimesFollowTheSweep(scan, 10.0);
    }
  }
}

// A beam's time (the scan's utime plus its beam time) is when the device measured it, in
// every packet format: a wall receding at 1 m/s shows each beam's time in its range.
TEST(RplidarDriver, BeamTimesAreWhenTheDeviceMeasured) {
  struct Case {
    const char* model;
    const char* mode;
    int baud;
  };
  const Case cases[] = {{"a1", "standard", 115200},
                        {"a2", "express", 115200},  // legacy capsules
                        {"s1", "auto", 256000},     // dense capsules
                        {"a3", "auto", 256000}};    // ultra capsules
  for (const Case& c : cases) {
    SCOPED_TRACE(c.model);
    const int64_t start_utime = HostClockUtime();
    RplidarEmulatorOptions device = RplidarEmulatorModel(c.model);
    device.range_m = [start_utime](double, int64_t measured_utime) {
      return 1.0 + std::clamp((measured_utime - start_utime) * 1e-6, 0.0, 8.0);
    };
    Rig rig(device, c.mode, c.baud);
    rig.driver.Start();
    const std::vector<LidarScan> scans = rig.Collect(3);
    ASSERT_EQ(scans.size(), 3u);
    std::vector<double> errors_ms;  // beam time - when its range was measured
    for (const LidarScan& scan : scans) {
      for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
        if (scan.range_m[i] <= 0.0f) continue;
        const double measured_s = scan.range_m[i] - 1.0;
        const double stamped_s = (scan.utime - start_utime) * 1e-6 + scan.beam_time_s[i];
        errors_ms.push_back((stamped_s - measured_s) * 1e3);
      }
    }
    ASSERT_GT(errors_ms.size(), 2u * scans[0].range_m.size());
    std::sort(errors_ms.begin(), errors_ms.end());
    // A packet's transfer (up to 7 ms at 115200 baud) or a packet's span of samples (8 ms in
    // legacy capsules) left out would shift the median by that much; millimetre ranges and
    // the pseudo-terminal's delivery blur each beam by a millisecond or two.
    EXPECT_NEAR(errors_ms[errors_ms.size() / 2], 0.0, 2.0);
    EXPECT_NEAR(errors_ms[errors_ms.size() / 20], 0.0, 10.0);
    EXPECT_NEAR(errors_ms[errors_ms.size() * 19 / 20], 0.0, 10.0);
  }
}

TEST(RplidarDriver, AnA3ListsItsModesAndScansInTheTypicalSensitivity) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
  device.range_m = Far;
  Rig rig(device, "auto", 256000);
  rig.driver.Start();
  const RplidarConnection& c = rig.driver.connection();
  ASSERT_EQ(c.scan_modes.size(), 5u);
  const char* names[] = {"Standard", "Express", "Boost", "Sensitivity", "Stability"};
  for (std::size_t id = 0; id < 5; ++id) {
    EXPECT_EQ(c.scan_modes[id].id, id);
    EXPECT_EQ(c.scan_modes[id].name, names[id]);
  }
  EXPECT_DOUBLE_EQ(c.scan_modes[4].us_per_sample, 100.0);
  EXPECT_DOUBLE_EQ(c.scan_modes[0].max_distance_m, 16.0);
  EXPECT_EQ(c.scan_modes[1].answer_type, 0x82);
  EXPECT_EQ(c.scan_modes[3].answer_type, 0x84);
  ASSERT_TRUE(c.typical_scan_mode);
  EXPECT_EQ(*c.typical_scan_mode, 3);
  EXPECT_EQ(c.scan_mode_name, "Sensitivity");
  EXPECT_EQ(c.format, rplidar::PacketFormat::kUltraCapsules);
  EXPECT_DOUBLE_EQ(c.sample_period_s, 62.5e-6);  // the mode's, not GET_SAMPLERATE's 126 us
  EXPECT_EQ(c.beams_per_revolution, 1600);       // 1 / (62.5 us * 10 Hz)
  EXPECT_EQ(c.range_max_m, 25.0);
  const Bytes sent = rig.emulator.ReceivedBytes();
  // After GET_SAMPLERATE the mode count is asked first: A5 84 04 70 00 00 00 55.
  const Bytes before_modes = {0xA5, 0x25, 0xA5, 0x50, 0xA5, 0x52, 0xA5, 0x59,
                              0xA5, 0x84, 0x04, 0x70, 0x00, 0x00, 0x00, 0x55};
  ASSERT_GE(sent.size(), before_modes.size());
  EXPECT_TRUE(std::equal(before_modes.begin(), before_modes.end(), sent.begin()));
  // EXPRESS_SCAN in working mode 3 (Sensitivity): checksum A5^82^05^03 = 0x21.
  EXPECT_TRUE(EndsWith(sent, {0xA5, 0x82, 0x05, 0x03, 0x00, 0x00, 0x00, 0x00, 0x21}));
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  for (const LidarScan& scan : scans) {
    // Half a beam (0.11 deg) at up to 9.5 m/rad, plus 16 mm steps beyond 16 m.
    ExpectRangesMatch(scan, Far, 0.04, 0.95);
    ExpectBeamTimesFollowTheSweep(scan, 10.0);
    EXPECT_EQ(scan.range_max_m, 25.0);
  }
  EXPECT_EQ(rig.driver.stats().checksum_errors, 0);
  EXPECT_EQ(rig.driver.stats().dropped_revolutions, 0);
  EXPECT_TRUE(Contains(rig.log, "scan mode Sensitivity: ultra capsules")) << rig.log.back();
}

TEST(RplidarDriver, ScanModeBoostPicksBoost) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
  device.range_m = Wavy;
  Rig rig(device, "boost", 256000);
  rig.driver.Start();
  EXPECT_EQ(rig.driver.connection().scan_mode_name, "Boost");
  EXPECT_EQ(rig.driver.connection().format, rplidar::PacketFormat::kUltraCapsules);
  // Working mode 2: checksum A5^82^05^02 = 0x20.
  EXPECT_TRUE(EndsWith(rig.emulator.ReceivedBytes(),
                       {0xA5, 0x82, 0x05, 0x02, 0x00, 0x00, 0x00, 0x00, 0x20}));
  const std::vector<LidarScan> scans = rig.Collect(2);
  ASSERT_EQ(scans.size(), 2u);
  for (const LidarScan& scan : scans) ExpectRangesMatch(scan, Wavy, 0.02, 0.95);
}

TEST(RplidarDriver, ScanModeStabilityTakesItsOwnSampleTime) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
  device.range_m = Smooth;
  Rig rig(device, "stability", 256000);
  rig.driver.Start();
  EXPECT_EQ(rig.driver.connection().scan_mode_name, "Stability");
  EXPECT_DOUBLE_EQ(rig.driver.connection().sample_period_s, 100e-6);
  EXPECT_EQ(rig.driver.connection().beams_per_revolution, 1000);
  const std::vector<LidarScan> scans = rig.Collect(2);
  ASSERT_EQ(scans.size(), 2u);
  for (const LidarScan& scan : scans) {
    ExpectRangesMatch(scan, Smooth, 0.02, 0.95);
    ExpectBeamTimesFollowTheSweep(scan, 10.0);
  }
}

TEST(RplidarDriver, WithoutAValidModeListTheModelsChoiceStays) {
  for (const bool error_answer : {true, false}) {
    SCOPED_TRACE(error_answer ? "wrong answers" : "no answers");
    RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
    device.range_m = Smooth;
    if (error_answer) {
      device.lidar_conf_error = true;  // answers echo another entry, with no value
    } else {
      device.scan_modes.clear();  // ignores GET_LIDAR_CONF, as firmware before 1.24 does
    }
    Rig rig(device, "auto", 256000);
    rig.driver.Start();
    const RplidarConnection& c = rig.driver.connection();
    EXPECT_TRUE(c.scan_modes.empty());
    EXPECT_FALSE(c.typical_scan_mode);
    EXPECT_TRUE(Contains(rig.log, "no valid answer to GET_LIDAR_CONF"))
        << ::testing::PrintToString(rig.log);
    const Bytes commands = rig.emulator.ReceivedCommands();
    EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x84), 1);  // asked once, gave up
    // Legacy EXPRESS_SCAN (working mode 0) at GET_SAMPLERATE's 126 us, as before.
    EXPECT_TRUE(EndsWith(rig.emulator.ReceivedBytes(),
                         {0xA5, 0x82, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x22}));
    EXPECT_EQ(c.format, rplidar::PacketFormat::kLegacyCapsules);
    EXPECT_EQ(c.beams_per_revolution, 790);
    const std::vector<LidarScan> scans = rig.Collect(2);
    ASSERT_EQ(scans.size(), 2u);
    for (const LidarScan& scan : scans) ExpectRangesMatch(scan, Smooth, 0.03, 0.9);
  }
}

TEST(RplidarDriver, OldFirmwareIsNotAskedForModes) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
  device.firmware_minor = 20;  // 1.20: before GET_LIDAR_CONF
  Rig rig(device, "auto", 256000);
  rig.driver.Start();
  const Bytes commands = rig.emulator.ReceivedCommands();
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x84), 0);
  EXPECT_EQ(rig.driver.connection().format, rplidar::PacketFormat::kLegacyCapsules);
  EXPECT_EQ(rig.Collect(1).size(), 1u);
}

TEST(RplidarDriver, AModeTheLidarDoesNotListFailsClearly) {
  const auto error_of = [](RplidarEmulatorOptions device, const std::string& mode) {
    Rig rig(std::move(device), mode, 256000);
    try {
      rig.driver.Start();
    } catch (const DeviceError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string unlisted = error_of(RplidarEmulatorModel("a3"), "denseboost");
  EXPECT_NE(unlisted.find("denseboost is not among the lidar's scan modes (Standard, Express, "
                          "Boost, Sensitivity, Stability)"),
            std::string::npos)
      << unlisted;
  const std::string no_list = error_of(RplidarEmulatorModel("a2"), "sensitivity");
  EXPECT_NE(no_list.find("sensitivity needs a lidar that lists its scan modes"), std::string::npos)
      << no_list;
}

TEST(RplidarDriver, GarbageBeforeSyncAndInTheStreamIsSkipped) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Smooth;
  // Includes a false capsule start (A? 5?) and a false descriptor start (A5 5A).
  device.garbage_before_first_packet = {0x13, 0xA5, 0x5A, 0x07, 0xA1, 0x52, 0x00, 0xFF, 0x42};
  Rig rig(device, "express");
  rig.driver.Start();
  ASSERT_EQ(rig.Collect(2).size(), 2u);
  rig.emulator.InjectGarbage({0x01, 0xA7, 0x5F, 0x99, 0x00, 0x12, 0x34, 0xA5});
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  for (const LidarScan& scan : scans) ExpectRangesMatch(scan, Smooth, 0.03, 0.85);
  EXPECT_GE(rig.driver.stats().discarded_bytes, 9);
}

TEST(RplidarDriver, GarbageInAStandardStreamIsSkipped) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a2");
  device.range_m = Smooth;
  Rig rig(device, "standard");
  rig.driver.Start();
  ASSERT_EQ(rig.Collect(1).size(), 1u);
  rig.emulator.InjectGarbage({0x00, 0x03, 0x11, 0x00, 0xFF, 0x3C, 0x00});
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  for (const LidarScan& scan : scans) ExpectRangesMatch(scan, Smooth, 0.04, 0.85);
}

TEST(RplidarDriver, ABadChecksumDropsOneCapsuleNotTheScans) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Smooth;
  Rig rig(device, "express");
  rig.driver.Start();
  ASSERT_EQ(rig.Collect(2).size(), 2u);
  rig.emulator.CorruptNextCapsule();
  const std::vector<LidarScan> scans = rig.Collect(3);
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_EQ(rig.driver.stats().checksum_errors, 1);
  EXPECT_EQ(rig.driver.stats().dropped_revolutions, 0);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ExpectRangesMatch(scans[i], Smooth, 0.03, 0.9);
    if (i > 0) {
      EXPECT_EQ(scans[i].seq, scans[i - 1].seq + 1);
    }
  }
}

TEST(RplidarDriver, AHealthWarningIsReportedAndScanningGoesOn) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.health_status = 1;
  device.health_error_code = 0x0042;
  Rig rig(device);
  rig.driver.Start();
  EXPECT_TRUE(Contains(rig.log, "WARNING (code 0x0042)")) << ::testing::PrintToString(rig.log);
  EXPECT_EQ(rig.Collect(2).size(), 2u);
  const Bytes commands = rig.emulator.ReceivedCommands();
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x40), 0);  // no RESET
}

TEST(RplidarDriver, AHealthErrorIsResetThenGivenUpOnWithAClearError) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.health_status = 2;
  device.health_error_code = 0x8001;
  device.health_error_survives_reset = true;
  Rig rig(device);
  std::string error;
  try {
    rig.driver.Start();
  } catch (const DeviceError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(rig.emulator.link_path()), std::string::npos) << error;
  EXPECT_NE(error.find("hardware error"), std::string::npos) << error;
  EXPECT_NE(error.find("0x8001"), std::string::npos) << error;
  const Bytes commands = rig.emulator.ReceivedCommands();
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x40), 1);  // one RESET
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x52), 2);  // health before and after
  EXPECT_EQ(std::count(commands.begin(), commands.end(), 0x20), 0);  // never a scan
}

TEST(RplidarDriver, AHealthErrorThatAResetClearsIsScannedThrough) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.health_status = 2;
  device.health_error_code = 0x8001;
  Rig rig(device);
  rig.driver.Start();
  EXPECT_EQ(rig.emulator.resets(), 1);
  EXPECT_EQ(rig.Collect(2).size(), 2u);
  EXPECT_EQ(rig.driver.connection().health.status, rplidar::HealthStatus::kGood);
}

TEST(RplidarDriver, AResetMidScanIsRecoveredFrom) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Smooth;
  Rig rig(device, "express");
  rig.driver.Start();
  ASSERT_EQ(rig.Collect(2).size(), 2u);
  rig.emulator.ResetNow();
  const std::vector<LidarScan> scans = rig.Collect(2);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(rig.driver.stats().restarts, 1);
  EXPECT_EQ(rig.emulator.scans_started(), 2);
  EXPECT_TRUE(Contains(rig.log, "restarting the scan"));
  for (const LidarScan& scan : scans) ExpectRangesMatch(scan, Smooth, 0.03, 0.9);
}

TEST(RplidarDriver, AWrongBaudRateFailsWithAClearErrorNotAHang) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a3");
  device.wrong_baud = true;
  Rig rig(device);
  std::string error;
  try {
    rig.driver.Start();
  } catch (const DeviceError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(rig.emulator.link_path()), std::string::npos) << error;
  EXPECT_NE(error.find("baud rate is probably wrong"), std::string::npos) << error;
  EXPECT_NE(error.find("256000"), std::string::npos) << error;  // what an A3 expects
}

TEST(RplidarLoop, UnplugAndReplugReconnectAndScansResume) {
  RplidarEmulatorOptions device = RplidarEmulatorModel("a1");
  device.range_m = Smooth;
  RplidarEmulator emulator(device);
  const RplidarOptions options = TestOptions(emulator.link_path());
  std::atomic<bool> stop{false};
  std::atomic<int> scans{0};
  std::mutex log_mutex;
  std::vector<std::string> log;
  const auto logged = [&](const std::string& text) {
    std::lock_guard<std::mutex> lock(log_mutex);
    return Contains(log, text);
  };
  std::thread loop([&] {
    RunRplidarLoop(
        options, stop, [&](const LidarScan&) { ++scans; },
        [&](const std::string& line) {
          std::lock_guard<std::mutex> lock(log_mutex);
          log.push_back(line);
        });
  });
  EXPECT_TRUE(WaitFor([&] { return scans >= 2; }, 10.0));
  emulator.Unplug();
  // The read fails ("gone"), then reopening fails while the link is missing.
  EXPECT_TRUE(WaitFor([&] { return logged("attempt 3 failed"); }, 10.0));
  const int before = scans;
  emulator.Replug();
  EXPECT_TRUE(WaitFor([&] { return scans >= before + 2; }, 10.0));
  stop = true;
  loop.join();
  EXPECT_TRUE(logged(emulator.link_path() + ": the device is gone"));
  EXPECT_TRUE(logged("serial port " + emulator.link_path() + ": no such device"));
  EXPECT_EQ(emulator.scans_started(), 2);
}

TEST(RplidarLoop, AMissingPortIsReportedEachAttemptAndGivenUpOnWhenAsked) {
  RplidarOptions options = TestOptions("/tmp/aslam_no_such_rplidar");
  std::atomic<bool> stop{false};
  std::vector<std::string> log;
  const int64_t scans = RunRplidarLoop(
      options, stop, [](const LidarScan&) {}, [&](const std::string& line) { log.push_back(line); },
      3);
  EXPECT_EQ(scans, 0);
  ASSERT_EQ(log.size(), 3u);
  for (const std::string& line : log) {
    EXPECT_NE(line.find("/tmp/aslam_no_such_rplidar: no such device"), std::string::npos) << line;
  }
  EXPECT_NE(log[0].find("retrying in 0.05 s"), std::string::npos) << log[0];
  EXPECT_NE(log[1].find("retrying in 0.10 s"), std::string::npos) << log[1];
  EXPECT_NE(log[2].find("giving up after 3 attempts"), std::string::npos) << log[2];
}

TEST(RplidarOptionsTest, ConfigErrorsNameFileKeyAndValue) {
  const auto error_of = [](const std::string& yaml) {
    try {
      LoadRplidarOptions(ConfigReader::FromString(yaml, "rplidar", "robot.yaml"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string model = error_of("rplidar:\n  model: a9\n");
  EXPECT_NE(model.find("robot.yaml"), std::string::npos) << model;
  EXPECT_NE(model.find("model"), std::string::npos) << model;
  EXPECT_NE(model.find("a9"), std::string::npos) << model;
  EXPECT_NE(error_of("rplidar:\n  scan_mode: turbo\n").find("scan_mode"), std::string::npos);
  EXPECT_NE(error_of("rplidar:\n  bauds: 115200\n").find("bauds"), std::string::npos);
  EXPECT_NE(error_of("rplidar:\n  reconnect_backoff_s: [2, 1]\n").find("reconnect_backoff_s"),
            std::string::npos);
  const RplidarOptions o = LoadRplidarOptions(ConfigReader::FromString(
      "rplidar:\n  port: /dev/ttyUSB1\n  baud: 256000\n  model: a3\n  scan_mode: express\n"
      "  reconnect_backoff_s: [1, 4]\n",
      "rplidar"));
  EXPECT_EQ(o.port, "/dev/ttyUSB1");
  EXPECT_EQ(o.baud, 256000);
  EXPECT_EQ(o.model, "a3");
  EXPECT_EQ(o.scan_mode, "express");
  EXPECT_EQ(LoadRplidarOptions(
                ConfigReader::FromString("rplidar:\n  scan_mode: sensitivity\n", "rplidar"))
                .scan_mode,
            "sensitivity");
  RplidarOptions boost;
  boost.scan_mode = "boost";
  EXPECT_NO_THROW(ValidateRplidarOptions(boost));
  boost.scan_mode = "Boost";  // names are given in lower case
  EXPECT_THROW(ValidateRplidarOptions(boost), std::invalid_argument);
  EXPECT_EQ(o.reconnect_backoff_initial_s, 1.0);
  EXPECT_EQ(o.reconnect_backoff_max_s, 4.0);
  EXPECT_EQ(ResolvedBaud(o), 256000);
  RplidarOptions s2;
  s2.model = "s2";
  EXPECT_EQ(ResolvedBaud(s2), 1000000);
}

TEST(RplidarOptionsTest, TheLidarMountComesFromTheRobotSection) {
  const std::string file = TestTempPath("mount.yaml");
  std::ofstream(file) << "robot:\n  lidar_mount: {x_m: 0.12, y_m: -0.03, yaw_rad: 3.14159}\n"
                         "rplidar:\n  port: /dev/rplidar\n";
  const RplidarOptions o = LoadRplidarOptionsFromFile(file);
  EXPECT_EQ(o.port, "/dev/rplidar");
  EXPECT_EQ(o.sensor_pose.x_m, 0.12);
  EXPECT_EQ(o.sensor_pose.y_m, -0.03);
  EXPECT_EQ(o.sensor_pose.yaw_rad, 3.14159);
}

}  // namespace
}  // namespace aslam
