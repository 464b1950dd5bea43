#pragma once

// A Slamtec RPLIDAR emulated on a pseudo-terminal, written from Slamtec's "RPLIDAR
// Interface Protocol and Application Notes" alone (it shares no code with the driver).
// It answers GET_INFO, GET_HEALTH, GET_SAMPLERATE, GET_LIDAR_CONF (scan modes, where
// configured), RESET (a boot banner, then deaf for the boot time), STOP, MOTOR_SPEED_CTRL,
// and streams SCAN nodes or EXPRESS_SCAN capsules (legacy, dense on S-series, or ultra
// for a listed Boost/Sensitivity/Stability mode) at the mode's sample rate from a range
// function, in its own thread. Faults can be injected: garbage, a capsule with a bad
// checksum, a health warning or error, a reset mid-scan, an unplug and a replug.
//
// The driver is given link_path(): a symlink the emulator re-points on replug, as udev
// re-points /dev/serial/by-id links.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/io/pseudo_terminal.h"

namespace aslam {

// A scan mode as GET_LIDAR_CONF reports it; its index in the list is its id.
struct RplidarEmulatorScanMode {
  std::string name;
  double us_per_sample = 0.0;
  double max_distance_m = 0.0;
  uint8_t answer_type = 0;  // 0x81 nodes, 0x82 legacy, 0x84 ultra, 0x85 dense capsules
};

struct RplidarEmulatorOptions {
  // Where the port's link is made ("" = in a temporary folder of the emulator's own).
  std::string link_path;
  // What GET_INFO reports.
  uint8_t model_byte = 0x18;
  uint8_t firmware_major = 1;
  uint8_t firmware_minor = 29;
  uint8_t hardware = 7;
  // What GET_SAMPLERATE reports, and the pace of the streams.
  uint16_t standard_sample_us = 508;
  uint16_t express_sample_us = 254;
  bool dense_express = false;  // EXPRESS_SCAN streams dense capsules (answer type 0x85)
  // Modes GET_LIDAR_CONF lists; empty = firmware without it (requests are ignored). EXPRESS_SCAN
  // with working mode 1.. starts the listed mode of that id; mode 0 stays legacy EXPRESS_SCAN.
  std::vector<RplidarEmulatorScanMode> scan_modes;
  uint16_t typical_scan_mode = 0;
  bool lidar_conf_error = false;  // GET_LIDAR_CONF answers echo the wrong type, no value
  uint32_t baud = 115200;  // the link's rate: a packet arrives its transfer time after it leaves
  double rotation_hz = 5.5;
  double start_angle_deg = 123.0;  // where the rotor points when a scan starts
  double time_scale = 1.0;         // emulated seconds per real second
  double boot_time_s = 0.05;       // after RESET, deaf for this long (real seconds)
  std::string boot_banner =
      "RP LIDAR System.\r\nFirmware Ver 1.29 - rc9, HW Ver 7\r\nModel: 18\r\n";
  // Distance seen at an angle (radians clockwise from the front, as the device measures) at
  // the instant the sample is measured (host clock, drivers/io/host_clock.h), which is before
  // the packet carrying it leaves. 0 or beyond the packet format's reach = no return.
  std::function<double(double angle_cw_rad, int64_t measured_utime)> range_m = [](double, int64_t) {
    return 2.0;
  };
  // Every answer arrives garbled, as at a wrong baud rate.
  bool wrong_baud = false;
  uint8_t health_status = 0;  // 0 good, 1 warning, 2 error
  uint16_t health_error_code = 0;
  bool health_error_survives_reset = false;
  // Bytes sent between a scan's response descriptor and its first packet.
  std::vector<uint8_t> garbage_before_first_packet;
};

// Defaults of a model ("a1", "a2", "a3", "s1", "s2"): identity, sample times, scan rate.
RplidarEmulatorOptions RplidarEmulatorModel(const std::string& name);

class RplidarEmulator {
 public:
  explicit RplidarEmulator(RplidarEmulatorOptions options);
  ~RplidarEmulator();
  RplidarEmulator(const RplidarEmulator&) = delete;
  RplidarEmulator& operator=(const RplidarEmulator&) = delete;

  // The symlink to give the driver (absent while unplugged).
  const std::string& link_path() const { return link_.path(); }

  // Injections, taking effect in the emulator's thread.
  void InjectGarbage(const std::vector<uint8_t>& bytes);
  void CorruptNextCapsule();
  void SetHealth(uint8_t status, uint16_t error_code, bool survives_reset);
  void ResetNow();  // as if the device browned out: banner, then idle
  void Unplug();    // both pty ends closed, the link removed
  void Replug();    // a new pseudo-terminal behind the link

  // Everything the driver wrote, in order, across plugs.
  std::vector<uint8_t> ReceivedBytes() const;
  // The commands received (the byte after A5), in order.
  std::vector<uint8_t> ReceivedCommands() const;
  int scans_started() const { return scans_started_; }
  int resets() const { return resets_; }
  int64_t packets_sent() const { return packets_sent_; }

 private:
  enum class Stream { kNone, kStandard, kLegacy, kDense, kUltra };
  void Run();
  void Send(const std::vector<uint8_t>& bytes);
  void HandleInput(const std::vector<uint8_t>& bytes);
  void HandleRequest(uint8_t command, const std::vector<uint8_t>& payload);
  void DoReset();
  void StartStream(Stream stream, double sample_us);
  void AnswerLidarConf(const std::vector<uint8_t>& payload);
  void StreamDue();
  double AngleAtSampleDeg(int64_t sample) const;
  // When `sample` of the current stream is measured, host clock.
  int64_t SampleUtime(int64_t sample) const;
  std::vector<uint8_t> StandardNode(int64_t sample);
  std::vector<uint8_t> CapsuleAt(int64_t capsule);
  std::vector<uint8_t> UltraCapsuleAt(int64_t capsule);
  // Checksum nibbles, and the injected corruption when one is pending.
  void SealCapsule(std::vector<uint8_t>* bytes);
  // The ultra capsule's start angle, q6 degrees, and its samples' distances in mm.
  int UltraStartQ6(int64_t capsule) const;
  uint32_t UltraSampleMm(int64_t capsule, int sample) const;

  RplidarEmulatorOptions options_;
  DeviceLink link_;
  mutable std::mutex mutex_;
  std::unique_ptr<PseudoTerminal> pty_;
  std::vector<uint8_t> input_;  // request bytes not yet complete
  std::vector<uint8_t> received_;
  std::vector<uint8_t> commands_;
  std::vector<uint8_t> pending_garbage_;
  bool corrupt_next_capsule_ = false;
  bool reset_requested_ = false;
  double deaf_until_s_ = 0.0;
  Stream stream_ = Stream::kNone;
  double stream_start_s_ = 0.0;   // host time the stream started
  double stream_period_s_ = 0.0;  // emulated seconds per sample
  double wire_free_s_ = 0.0;      // host time the last packet sent has arrived
  int64_t next_packet_ = 0;
  uint32_t noise_state_ = 12345;
  std::atomic<int> scans_started_{0};
  std::atomic<int> resets_{0};
  std::atomic<int64_t> packets_sent_{0};
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace aslam
