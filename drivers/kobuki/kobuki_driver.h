#pragma once

// The Kobuki base driver over a ByteStream (a serial port, or a pseudo-terminal in tests):
// feedback packets become odometry and the base's status; each is answered with a Base
// Control from the safety layer (base_safety.h). No LCM here (kobuki_lcm.h publishes).

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/config.h"
#include "common/sensor_types.h"
#include "drivers/io/byte_stream.h"
#include "drivers/io/device_clock.h"
#include "drivers/io/driver_status.h"
#include "drivers/kobuki/base_safety.h"
#include "drivers/kobuki/kobuki_odometry.h"
#include "drivers/kobuki/kobuki_protocol.h"

namespace aslam {

// The `kobuki:` config section (speed and acceleration limits come from the `robot:`
// section); the flags of aslam-kobuki override the port.
struct KobukiOptions {
  std::string port = "/dev/kobuki";  // the udev link of config/udev/99-aslam.rules
  KobukiGeometry geometry;
  bool gyro_heading = true;  // heading: gyro, else encoders
  BaseSafetyOptions safety;
  double status_rate_hz = 10.0;     // BASE_STATUS, besides at every hazard change
  double response_timeout_s = 1.0;  // no valid feedback this long: the base is gone
  double reconnect_backoff_initial_s = 0.5;
  double reconnect_backoff_max_s = 8.0;
};

// Reads and validates the section (errors name file, key and value).
KobukiOptions LoadKobukiOptions(const ConfigReader& section);
// The `kobuki:` and `robot:` sections of `file`; "" = defaults.
KobukiOptions LoadKobukiOptionsFromFile(const std::string& file);
// Checks values set in code or by flags; throws std::invalid_argument saying what is wrong.
void ValidateKobukiOptions(const KobukiOptions& options);

// The base as BASE_STATUS reports it.
struct KobukiStatus {
  int64_t utime = 0;
  std::string device;
  bool connected = false;
  kobuki::BasicSensorData sensors;
  bool hazard_stop = false;
  bool command_timeout = true;
  Twist commanded;
  std::string hardware_version, firmware_version, unique_id;
  int64_t feedback_packets = 0;
  int64_t checksum_errors = 0;
  int64_t discarded_bytes = 0;
  int reconnects = 0;
};

class KobukiDriver {
 public:
  using Log = std::function<void(const std::string&)>;

  // `log` gets one line per notable event (default: stderr).
  explicit KobukiDriver(KobukiOptions options, Log log = {});

  // Talks to the base on `stream` from now on: waits for a valid feedback packet (for
  // response_timeout_s) and asks for the versions and the unique id. Throws DeviceError
  // naming the port and what to check.
  void Connect(ByteStream& stream);
  // The stream is gone. At the next Connect odometry counts the motion in between if the
  // base ran on, else (power-cycled) continues from the same pose.
  void Disconnect();
  // Reads for at most timeout_ms; each feedback packet appends odometry and is answered
  // with a Base Control. Returns true when a hazard (bumper, cliff, wheel drop) or the
  // hazard stop changed. Throws DeviceError when the port fails or stays silent.
  bool Poll(int timeout_ms, std::vector<Odometry>* odometry);
  // A CMD_VEL as it arrived (host clock); false if refused (not finite).
  bool OnCommand(const VelocityCommand& command, int64_t arrival_utime);
  // Sends a zero Base Control, best effort: never throws.
  void StopBase() noexcept;

  KobukiStatus status() const;
  DriverStatus driver_status() const;
  bool connected() const { return stream_ != nullptr; }

 private:
  // Handles one payload; returns whether a hazard changed.
  bool HandleFeedback(const kobuki::Feedback& feedback, int64_t arrival_utime);
  void Send(const std::vector<uint8_t>& payload);
  int64_t DeviceUtime(uint16_t timestamp_ms);

  KobukiOptions options_;
  Log log_;
  ByteStream* stream_ = nullptr;
  kobuki::PacketParser parser_;
  int64_t parser_checksum_errors_base_ = 0;  // earlier connections' counts
  int64_t parser_discarded_base_ = 0;
  int64_t malformed_packets_ = 0;
  KobukiOdometry odometry_;
  BaseSafety safety_;
  DeviceClock clock_;
  RateCounter published_;
  std::optional<uint16_t> last_timestamp_ms_;
  int64_t device_ms_ = 0;      // the base's clock, unwrapped
  bool resume_check_ = false;  // the next feedback is the first after a reconnect
  int64_t last_feedback_utime_ = 0;
  int64_t last_request_utime_ = 0;
  int requests_sent_ = 0;
  KobukiStatus status_;
  std::string last_event_;
};

// Opens options.port as a serial port (115200 baud), runs the driver and calls on_odometry
// per feedback and on_status at options.status_rate_hz and at hazard changes, and `service`
// between reads (the caller's LCM handling) until `stop`; on a DeviceError (unplug,
// silence) stops using the port and retries with exponential backoff, logging each attempt.
// Returns after `max_attempts` failed attempts in a row (0 = never gives up) or on `stop`.
struct KobukiLoopCallbacks {
  std::function<void()> service;
  std::function<void(const Odometry&)> on_odometry;
  std::function<void(const KobukiStatus&, const DriverStatus&)> on_status;
};
void RunKobukiLoop(KobukiDriver& driver, const KobukiOptions& options,
                   const std::atomic<bool>& stop, const KobukiLoopCallbacks& callbacks,
                   const KobukiDriver::Log& log = {}, int max_attempts = 0);

}  // namespace aslam
