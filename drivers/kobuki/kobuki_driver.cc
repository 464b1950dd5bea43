#include "drivers/kobuki/kobuki_driver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "common/robot_config.h"
#include "drivers/io/backoff_config.h"
#include "drivers/io/host_clock.h"
#include "drivers/io/serial_port.h"

namespace aslam {
namespace {

constexpr uint16_t kAllExtras = kobuki::kRequestHardwareVersion | kobuki::kRequestFirmwareVersion |
                                kobuki::kRequestUniqueDeviceId;
constexpr int kMaxExtraRequests = 5;  // then the base is used without knowing its versions
// Encoder counts carry across a disconnect this long (at most 0.7 m/s, within 16 bits).
constexpr double kMaxCountedGapMs = 3000.0;
// The base's and the host's clocks agree on a gap this closely when nothing restarted.
constexpr double kClockAgreementMs = 250.0;

std::string HexId(const std::array<uint32_t, 3>& id) {
  char text[32];
  std::snprintf(text, sizeof(text), "%08X-%08X-%08X", id[0], id[1], id[2]);
  return text;
}

void DefaultLog(const std::string& line) {
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace

KobukiOptions LoadKobukiOptions(const ConfigReader& c) {
  KobukiOptions o;
  c.Read("port", &o.port);
  c.ReadInRange("wheel_radius_m", &o.geometry.wheel_radius_m, 0.005, 1.0);
  c.ReadInRange("wheel_base_m", &o.geometry.wheel_base_m, 0.02, 5.0);
  c.ReadInRange("ticks_per_revolution", &o.geometry.ticks_per_revolution, 1.0, 1e6);
  std::string heading = o.gyro_heading ? "gyro" : "encoders";
  c.Read("heading", &heading);
  if (heading != "gyro" && heading != "encoders") c.Fail("heading", "must be gyro or encoders");
  o.gyro_heading = heading == "gyro";
  c.ReadInRange("command_timeout_s", &o.safety.command_timeout_s, 0.02, 10.0);
  c.ReadInRange("status_rate_hz", &o.status_rate_hz, 0.1, 50.0);
  c.ReadInRange("response_timeout_s", &o.response_timeout_s, 0.05, 30.0);
  ReadReconnectBackoff(c, &o.reconnect_backoff_initial_s, &o.reconnect_backoff_max_s);
  c.CheckAllKeysUsed();
  return o;
}

KobukiOptions LoadKobukiOptionsFromFile(const std::string& file) {
  KobukiOptions options = LoadKobukiOptions(ConfigReader::FromOptionalFile(file, "kobuki"));
  const RobotOptions robot = LoadRobotOptionsFromFile(file);
  options.safety.max_linear_mps = robot.max_linear_mps;
  options.safety.max_angular_radps = robot.max_angular_radps;
  options.safety.max_linear_accel_mps2 = robot.max_linear_accel_mps2;
  options.safety.max_angular_accel_radps2 = robot.max_angular_accel_radps2;
  return options;
}

void ValidateKobukiOptions(const KobukiOptions& o) {
  if (o.port.empty()) throw std::invalid_argument("port is empty (e.g. /dev/kobuki)");
  if (!(o.geometry.wheel_radius_m > 0) || !(o.geometry.wheel_base_m > 0) ||
      !(o.geometry.ticks_per_revolution > 0)) {
    throw std::invalid_argument("wheel radius, wheel base and ticks per revolution must be > 0");
  }
  if (!(o.safety.command_timeout_s > 0)) {
    throw std::invalid_argument("command_timeout_s must be > 0");
  }
  if (o.reconnect_backoff_initial_s <= 0 ||
      o.reconnect_backoff_max_s < o.reconnect_backoff_initial_s) {
    throw std::invalid_argument("reconnect backoff must be 0 < initial <= max");
  }
}

KobukiDriver::KobukiDriver(KobukiOptions options, Log log)
    : options_(std::move(options)),
      log_(log ? std::move(log) : Log(DefaultLog)),
      odometry_(options_.geometry, options_.gyro_heading),
      safety_(options_.safety) {
  status_.device = options_.port;
}

void KobukiDriver::Send(const std::vector<uint8_t>& payload) {
  const std::vector<uint8_t> packet = kobuki::EncodePacket(payload);
  stream_->Write(packet.data(), packet.size());
}

void KobukiDriver::Connect(ByteStream& stream) {
  stream_ = &stream;
  parser_ = kobuki::PacketParser();
  const int64_t packets_before = status_.feedback_packets;
  resume_check_ = packets_before > 0;
  stream.DiscardInput();
  const int64_t deadline = HostClockUtime() + std::llround(options_.response_timeout_s * 1e6);
  int64_t bytes = 0;
  std::vector<Odometry> ignored;
  while (status_.feedback_packets == packets_before) {
    const int64_t now = HostClockUtime();
    if (now >= deadline) {
      stream_ = nullptr;
      char text[256];
      std::snprintf(text, sizeof(text), "%s: no Kobuki feedback within %.1f s ",
                    stream.name().c_str(), options_.response_timeout_s);
      throw DeviceError(std::string(text) +
                        (bytes == 0 ? "(nothing arrived): is the base switched on, and is this "
                                      "its port?"
                                    : "(" + std::to_string(bytes) +
                                          " bytes arrived, none a valid packet): is this a "
                                          "Kobuki at 115200 baud?"));
    }
    uint8_t buffer[512];
    const std::size_t n =
        stream.Read(buffer, sizeof(buffer), static_cast<int>((deadline - now + 999) / 1000));
    bytes += static_cast<int64_t>(n);
    std::vector<std::vector<uint8_t>> payloads;
    parser_.Push(buffer, n, &payloads);
    for (const auto& payload : payloads) {
      const auto feedback = kobuki::ParseFeedback(payload);
      if (feedback && feedback->basic) HandleFeedback(*feedback, HostClockUtime());
    }
  }
  Send(kobuki::RequestExtraSubPayload(kAllExtras));
  last_request_utime_ = HostClockUtime();
  requests_sent_ = 1;
  status_.connected = true;
  last_event_ = "connected to " + stream.name();
  log_("aslam-kobuki: " + last_event_);
}

void KobukiDriver::Disconnect() {
  if (stream_ == nullptr) return;
  stream_ = nullptr;
  status_.connected = false;
  parser_checksum_errors_base_ += parser_.checksum_errors();
  parser_discarded_base_ += parser_.discarded_bytes();
  parser_ = kobuki::PacketParser();
  ++status_.reconnects;
}

int64_t KobukiDriver::DeviceUtime(uint16_t timestamp_ms) {
  if (last_timestamp_ms_) device_ms_ += static_cast<uint16_t>(timestamp_ms - *last_timestamp_ms_);
  last_timestamp_ms_ = timestamp_ms;
  return device_ms_ * 1000;
}

bool KobukiDriver::HandleFeedback(const kobuki::Feedback& feedback, int64_t arrival_utime) {
  if (feedback.hardware_version) status_.hardware_version = feedback.hardware_version->ToString();
  if (feedback.firmware_version) status_.firmware_version = feedback.firmware_version->ToString();
  if (feedback.unique_id) status_.unique_id = HexId(*feedback.unique_id);
  if (!feedback.basic) return false;
  const kobuki::BasicSensorData& basic = *feedback.basic;
  if (resume_check_) {
    resume_check_ = false;
    // Back after a disconnect: the same base, still counting, if its clock ran on with the
    // host's; else (power-cycled) odometry starts over from the last pose.
    const double gap_ms = (arrival_utime - last_feedback_utime_) * 1e-3;
    const int device_gap_ms =
        static_cast<uint16_t>(basic.timestamp_ms - status_.sensors.timestamp_ms);
    if (gap_ms > kMaxCountedGapMs || std::abs(device_gap_ms - gap_ms) > kClockAgreementMs) {
      odometry_.Restart();
      clock_.Reset();
      last_timestamp_ms_.reset();
      last_event_ = "the base restarted while away: odometry goes on from its last pose";
      log_("aslam-kobuki: " + last_event_);
    }
  }
  ++status_.feedback_packets;
  last_feedback_utime_ = arrival_utime;
  const int64_t utime = clock_.Map(DeviceUtime(basic.timestamp_ms), arrival_utime);
  const bool was_stopped = safety_.hazard_stop();
  const kobuki::BasicSensorData before = status_.sensors;
  status_.sensors = basic;
  status_.utime = utime;
  safety_.OnHazards(basic.bumper, basic.cliff, basic.wheel_drop, arrival_utime);
  if (safety_.hazard_stop() && !was_stopped) {
    char text[96];
    std::snprintf(text, sizeof(text), "stopped: bumper 0x%02x, cliff 0x%02x, wheel drop 0x%02x",
                  basic.bumper, basic.cliff, basic.wheel_drop);
    last_event_ = text;
    log_(std::string("aslam-kobuki: ") + text);
  }
  return was_stopped != safety_.hazard_stop() || before.bumper != basic.bumper ||
         before.cliff != basic.cliff || before.wheel_drop != basic.wheel_drop;
}

bool KobukiDriver::Poll(int timeout_ms, std::vector<Odometry>* odometry) {
  if (stream_ == nullptr) throw DeviceError(options_.port + ": not connected");
  uint8_t buffer[512];
  const std::size_t n = stream_->Read(buffer, sizeof(buffer), timeout_ms);
  const int64_t arrival = HostClockUtime();
  std::vector<std::vector<uint8_t>> payloads;
  parser_.Push(buffer, n, &payloads);
  bool changed = false;
  for (const auto& payload : payloads) {
    const auto feedback = kobuki::ParseFeedback(payload);
    if (!feedback) {
      ++malformed_packets_;  // a sub-payload runs past the end, or a known one is mis-sized
      continue;
    }
    changed |= HandleFeedback(*feedback, arrival);
    if (!feedback->basic) continue;
    if (auto sample = odometry_.Update(status_.utime, *feedback->basic, feedback->inertial)) {
      odometry->push_back(*sample);
      published_.Count(arrival);
    }
    const Twist twist = safety_.Next(arrival);
    const kobuki::BaseControl control = kobuki::BaseControlFromTwist(
        twist.linear_mps, twist.angular_radps, options_.geometry.wheel_base_m);
    std::vector<uint8_t> out = kobuki::BaseControlSubPayload(control.speed_mm_s, control.radius_mm);
    const bool extras_missing = status_.hardware_version.empty() ||
                                status_.firmware_version.empty() || status_.unique_id.empty();
    if (extras_missing && requests_sent_ < kMaxExtraRequests &&
        arrival - last_request_utime_ > 1e6) {
      const std::vector<uint8_t> request = kobuki::RequestExtraSubPayload(kAllExtras);
      out.insert(out.end(), request.begin(), request.end());
      last_request_utime_ = arrival;
      ++requests_sent_;
    }
    Send(out);
    status_.commanded = twist;
  }
  if (arrival - last_feedback_utime_ > options_.response_timeout_s * 1e6) {
    throw DeviceError(options_.port + ": no feedback from the Kobuki for " +
                      std::to_string(options_.response_timeout_s).substr(0, 4) + " s");
  }
  return changed;
}

bool KobukiDriver::OnCommand(const VelocityCommand& command, int64_t arrival_utime) {
  return safety_.OnCommand(command, arrival_utime);
}

void KobukiDriver::StopBase() noexcept {
  if (stream_ == nullptr) return;
  try {
    Send(kobuki::BaseControlSubPayload(0, 0));
  } catch (...) {
    // The port is gone: there is nothing to send the stop on.
  }
}

KobukiStatus KobukiDriver::status() const {
  KobukiStatus status = status_;
  status.utime = HostClockUtime();
  status.hazard_stop = safety_.hazard_stop();
  status.command_timeout = safety_.command_timed_out();
  status.checksum_errors = parser_checksum_errors_base_ + parser_.checksum_errors();
  status.discarded_bytes = parser_discarded_base_ + parser_.discarded_bytes();
  return status;
}

DriverStatus KobukiDriver::driver_status() const {
  DriverStatus s;
  s.utime = HostClockUtime();
  s.driver = "aslam-kobuki";
  s.device = options_.port;
  s.connected = connected();
  s.messages = published_.total();
  s.rate_hz = published_.rate_hz(s.utime);
  s.clock_offset_ms = clock_.offset_ms();
  s.clock_jitter_ms = clock_.jitter_ms();
  s.errors = parser_checksum_errors_base_ + parser_.checksum_errors() + malformed_packets_;
  s.reconnects = status_.reconnects;
  s.detail = last_event_;
  return s;
}

void RunKobukiLoop(KobukiDriver& driver, const KobukiOptions& options,
                   const std::atomic<bool>& stop, const KobukiLoopCallbacks& callbacks,
                   const KobukiDriver::Log& log_in, int max_attempts) {
  const KobukiDriver::Log log = log_in ? log_in : KobukiDriver::Log(DefaultLog);
  const int64_t status_period_us = std::llround(1e6 / options.status_rate_hz);
  int64_t next_status_utime = 0;
  auto publish_status = [&] {
    if (callbacks.on_status) callbacks.on_status(driver.status(), driver.driver_status());
    next_status_utime = HostClockUtime() + status_period_us;
  };
  double backoff_s = options.reconnect_backoff_initial_s;
  int failures = 0;
  std::vector<Odometry> odometry;
  while (!stop) {
    try {
      SerialPort port(options.port, kobuki::kBaud);
      driver.Connect(port);
      failures = 0;
      backoff_s = options.reconnect_backoff_initial_s;
      publish_status();
      while (!stop) {
        if (callbacks.service) callbacks.service();
        odometry.clear();
        const bool changed = driver.Poll(10, &odometry);
        for (const Odometry& sample : odometry) {
          if (callbacks.on_odometry) callbacks.on_odometry(sample);
        }
        if (changed || HostClockUtime() >= next_status_utime) publish_status();
      }
      driver.StopBase();
      driver.Disconnect();
      publish_status();
      return;
    } catch (const DeviceError& e) {
      driver.Disconnect();
      ++failures;
      publish_status();
      if (max_attempts > 0 && failures >= max_attempts) {
        log(std::string("aslam-kobuki: ") + e.what() + "; giving up after " +
            std::to_string(failures) + " attempts");
        return;
      }
      char line[64];
      std::snprintf(line, sizeof(line), "; attempt %d failed, retrying in %.2f s", failures,
                    backoff_s);
      log(std::string("aslam-kobuki: ") + e.what() + line);
    }
    // Wait out the backoff in small steps, still serving the bus and honouring a stop.
    const int64_t wake = HostClockUtime() + static_cast<int64_t>(backoff_s * 1e6);
    while (!stop && HostClockUtime() < wake) {
      if (callbacks.service) callbacks.service();
      if (HostClockUtime() >= next_status_utime) publish_status();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    backoff_s = std::min(backoff_s * 2.0, options.reconnect_backoff_max_s);
  }
}

}  // namespace aslam
