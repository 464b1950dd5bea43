#pragma once

// The Kobuki serial protocol (Yujin Robot's "Kobuki Protocol Specification"): packets of
// 0xAA 0x55, a length byte, a payload of sub-payloads (id, length, data; little-endian)
// and an XOR checksum over the length and payload; the commands the driver sends and the
// feedback the base streams every 20 ms. No I/O here.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace aslam::kobuki {

inline constexpr uint8_t kHeader0 = 0xAA;
inline constexpr uint8_t kHeader1 = 0x55;
inline constexpr int kBaud = 115200;

// Command sub-payload ids.
inline constexpr uint8_t kBaseControlId = 1;
inline constexpr uint8_t kRequestExtraId = 9;
// Request Extra flags.
inline constexpr uint16_t kRequestHardwareVersion = 0x01;
inline constexpr uint16_t kRequestFirmwareVersion = 0x02;
inline constexpr uint16_t kRequestUniqueDeviceId = 0x08;

// Feedback sub-payload ids, and the data lengths the specification fixes.
inline constexpr uint8_t kBasicSensorDataId = 1;
inline constexpr uint8_t kBasicSensorDataLength = 15;
inline constexpr uint8_t kInertialSensorDataId = 4;
inline constexpr uint8_t kInertialSensorDataLength = 7;
inline constexpr uint8_t kHardwareVersionId = 10;
inline constexpr uint8_t kFirmwareVersionId = 11;
inline constexpr uint8_t kVersionLength = 4;
inline constexpr uint8_t kUniqueDeviceIdId = 19;
inline constexpr uint8_t kUniqueDeviceIdLength = 12;

// Basic sensor data flags.
inline constexpr uint8_t kBumperRight = 0x01, kBumperCentral = 0x02, kBumperLeft = 0x04;
inline constexpr uint8_t kWheelDropRight = 0x01, kWheelDropLeft = 0x02;
inline constexpr uint8_t kCliffRight = 0x01, kCliffCentral = 0x02, kCliffLeft = 0x04;

// The whole packet around `payload` (at most 255 bytes).
std::vector<uint8_t> EncodePacket(const std::vector<uint8_t>& payload);
// Sub-payloads, to concatenate into one packet's payload.
std::vector<uint8_t> BaseControlSubPayload(int16_t speed_mm_s, int16_t radius_mm);
std::vector<uint8_t> RequestExtraSubPayload(uint16_t flags);

// Base Control's two numbers: radius 0 drives straight at `speed`; radius 1 turns in place
// with `speed` the wheels' speed (positive counter-clockwise); any other radius drives an
// arc (positive to the left) with `speed` the outer wheel's speed.
struct BaseControl {
  int16_t speed_mm_s = 0;
  int16_t radius_mm = 0;
};
// The Base Control that drives at (linear, angular) on a base with this wheel base; arcs
// wider than the radius field holds are driven straight.
BaseControl BaseControlFromTwist(double linear_mps, double angular_radps, double wheel_base_m);

struct BasicSensorData {
  uint16_t timestamp_ms = 0;  // the base's clock, wrapping at 65536
  uint8_t bumper = 0;
  uint8_t wheel_drop = 0;
  uint8_t cliff = 0;
  uint16_t left_encoder = 0;  // ticks, wrapping at 65536
  uint16_t right_encoder = 0;
  int8_t left_pwm = 0;
  int8_t right_pwm = 0;
  uint8_t buttons = 0;
  uint8_t charger = 0;
  uint8_t battery_dv = 0;  // 0.1 V
  uint8_t overcurrent = 0;
};

struct InertialSensorData {
  int16_t angle_cdeg = 0;       // heading, 0.01°, counter-clockwise
  int16_t angle_rate_cdeg = 0;  // 0.01°/s
};

struct Version {
  uint8_t major = 0, minor = 0, patch = 0;
  std::string ToString() const;
};

// What one feedback packet carried; sub-payloads the driver does not use are counted.
struct Feedback {
  std::optional<BasicSensorData> basic;
  std::optional<InertialSensorData> inertial;
  std::optional<Version> hardware_version;
  std::optional<Version> firmware_version;
  std::optional<std::array<uint32_t, 3>> unique_id;
  int other_sub_payloads = 0;
};

// Splits a feedback payload into sub-payloads; nullopt when one runs past the end or a
// used one has the wrong length (the packet is malformed).
std::optional<Feedback> ParseFeedback(const std::vector<uint8_t>& payload);

// Finds packets in a byte stream: resynchronises on 0xAA 0x55 after garbage, and drops a
// packet whose checksum is wrong by searching again one byte after its header.
class PacketParser {
 public:
  // Appends `size` bytes and moves the payloads of the complete, valid packets to *payloads.
  void Push(const uint8_t* data, std::size_t size, std::vector<std::vector<uint8_t>>* payloads);
  int64_t checksum_errors() const { return checksum_errors_; }
  int64_t discarded_bytes() const { return discarded_bytes_; }

 private:
  std::vector<uint8_t> buffer_;
  int64_t checksum_errors_ = 0;
  int64_t discarded_bytes_ = 0;
};

}  // namespace aslam::kobuki
