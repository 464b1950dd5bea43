#include "drivers/kobuki/kobuki_protocol.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aslam::kobuki {
namespace {

void PutU16(std::vector<uint8_t>* bytes, uint16_t value) {
  bytes->push_back(static_cast<uint8_t>(value & 0xFF));
  bytes->push_back(static_cast<uint8_t>(value >> 8));
}

uint16_t U16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t U32(const uint8_t* p) {
  return static_cast<uint32_t>(U16(p)) | (static_cast<uint32_t>(U16(p + 2)) << 16);
}

int16_t ClampToInt16(double value) {
  return static_cast<int16_t>(std::clamp(std::lround(value), -32768L, 32767L));
}

// Smallest packet: a sub-payload with one data byte (the specification's minimum length 3).
constexpr std::size_t kMinPayload = 3;

}  // namespace

std::vector<uint8_t> EncodePacket(const std::vector<uint8_t>& payload) {
  if (payload.size() < kMinPayload || payload.size() > 255) {
    throw std::invalid_argument("a Kobuki payload has 3 to 255 bytes, not " +
                                std::to_string(payload.size()));
  }
  std::vector<uint8_t> packet = {kHeader0, kHeader1, static_cast<uint8_t>(payload.size())};
  uint8_t checksum = packet[2];
  for (uint8_t byte : payload) {
    packet.push_back(byte);
    checksum ^= byte;
  }
  packet.push_back(checksum);
  return packet;
}

std::vector<uint8_t> BaseControlSubPayload(int16_t speed_mm_s, int16_t radius_mm) {
  std::vector<uint8_t> bytes = {kBaseControlId, 4};
  PutU16(&bytes, static_cast<uint16_t>(speed_mm_s));
  PutU16(&bytes, static_cast<uint16_t>(radius_mm));
  return bytes;
}

std::vector<uint8_t> RequestExtraSubPayload(uint16_t flags) {
  std::vector<uint8_t> bytes = {kRequestExtraId, 2};
  PutU16(&bytes, flags);
  return bytes;
}

BaseControl BaseControlFromTwist(double linear_mps, double angular_radps, double wheel_base_m) {
  constexpr double kStill = 1e-4;
  const double half_base_mm = wheel_base_m * 500.0;
  if (std::abs(angular_radps) < kStill) return {ClampToInt16(linear_mps * 1000.0), 0};
  const double radius_mm = linear_mps * 1000.0 / angular_radps;
  // Radius ±1 (and 0) are codes, not arcs: anything that tight is a turn in place.
  if (std::abs(linear_mps) < kStill || std::abs(radius_mm) < 2.0) {
    return {ClampToInt16(angular_radps * half_base_mm), 1};
  }
  if (std::abs(radius_mm) > 32767.0) return {ClampToInt16(linear_mps * 1000.0), 0};
  const double outer_mm = radius_mm > 0 ? radius_mm + half_base_mm : radius_mm - half_base_mm;
  return {ClampToInt16(outer_mm * angular_radps), ClampToInt16(radius_mm)};
}

std::string Version::ToString() const {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

std::optional<Feedback> ParseFeedback(const std::vector<uint8_t>& payload) {
  Feedback feedback;
  std::size_t at = 0;
  while (at < payload.size()) {
    if (at + 2 > payload.size()) return std::nullopt;
    const uint8_t id = payload[at];
    const uint8_t length = payload[at + 1];
    const uint8_t* d = payload.data() + at + 2;
    if (at + 2 + length > payload.size()) return std::nullopt;
    at += 2 + length;
    switch (id) {
      case kBasicSensorDataId: {
        if (length != kBasicSensorDataLength) return std::nullopt;
        BasicSensorData b;
        b.timestamp_ms = U16(d);
        b.bumper = d[2];
        b.wheel_drop = d[3];
        b.cliff = d[4];
        b.left_encoder = U16(d + 5);
        b.right_encoder = U16(d + 7);
        b.left_pwm = static_cast<int8_t>(d[9]);
        b.right_pwm = static_cast<int8_t>(d[10]);
        b.buttons = d[11];
        b.charger = d[12];
        b.battery_dv = d[13];
        b.overcurrent = d[14];
        feedback.basic = b;
        break;
      }
      case kInertialSensorDataId:
        if (length != kInertialSensorDataLength) return std::nullopt;
        feedback.inertial =
            InertialSensorData{static_cast<int16_t>(U16(d)), static_cast<int16_t>(U16(d + 2))};
        break;
      case kHardwareVersionId:
      case kFirmwareVersionId: {
        if (length != kVersionLength) return std::nullopt;
        // Patch, minor, major, then an unused byte.
        const Version version{d[2], d[1], d[0]};
        (id == kHardwareVersionId ? feedback.hardware_version : feedback.firmware_version) =
            version;
        break;
      }
      case kUniqueDeviceIdId:
        if (length != kUniqueDeviceIdLength) return std::nullopt;
        feedback.unique_id = std::array<uint32_t, 3>{U32(d), U32(d + 4), U32(d + 8)};
        break;
      default: ++feedback.other_sub_payloads;
    }
  }
  return feedback;
}

void PacketParser::Push(const uint8_t* data, std::size_t size,
                        std::vector<std::vector<uint8_t>>* payloads) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::size_t at = 0;
  while (true) {
    // The next header; bytes before it are noise.
    std::size_t start = at;
    while (start + 1 < buffer_.size() &&
           !(buffer_[start] == kHeader0 && buffer_[start + 1] == kHeader1)) {
      ++start;
    }
    if (start + 1 >= buffer_.size()) {
      // Keep a trailing 0xAA: it may be the first half of a header.
      const std::size_t keep = !buffer_.empty() && buffer_.back() == kHeader0 ? 1 : 0;
      discarded_bytes_ += static_cast<int64_t>(buffer_.size() - keep - at);
      at = buffer_.size() - keep;
      break;
    }
    discarded_bytes_ += static_cast<int64_t>(start - at);
    at = start;
    if (at + 3 > buffer_.size()) break;  // the length has not arrived
    const std::size_t length = buffer_[at + 2];
    if (length < kMinPayload) {
      ++discarded_bytes_;  // not a packet: look again past this header byte
      ++at;
      continue;
    }
    if (at + 3 + length + 1 > buffer_.size()) break;  // the rest has not arrived
    uint8_t checksum = 0;
    for (std::size_t i = at + 2; i < at + 3 + length + 1; ++i) checksum ^= buffer_[i];
    if (checksum != 0) {
      ++checksum_errors_;
      ++discarded_bytes_;
      ++at;
      continue;
    }
    payloads->emplace_back(buffer_.begin() + static_cast<std::ptrdiff_t>(at + 3),
                           buffer_.begin() + static_cast<std::ptrdiff_t>(at + 3 + length));
    at += 3 + length + 1;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(at));
}

}  // namespace aslam::kobuki
