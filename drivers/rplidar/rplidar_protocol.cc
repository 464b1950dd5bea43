#include "drivers/rplidar/rplidar_protocol.h"

#include <cmath>
#include <cstdio>

namespace aslam::rplidar {
namespace {

uint16_t U16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }

// Defaults per model. Baud rates: the models' datasheets and Slamtec's rplidar_ros launch
// files (A1/A2M8 115200, A2M12/A3/S1 256000, S2 1000000). Ranges and scan rates: datasheets.
const ModelDefaults kA1{"a1", 115200, 5.5, 0.15, 12.0, MotorControl::kDtr, 0};
const ModelDefaults kA2{"a2", 115200, 10.0, 0.15, 12.0, MotorControl::kDtr, 0};
const ModelDefaults kA3{"a3", 256000, 10.0, 0.2, 25.0, MotorControl::kDtr, 0};
const ModelDefaults kS1{"s1", 256000, 10.0, 0.1, 40.0, MotorControl::kSpeedCommand, 1};
const ModelDefaults kS2{"s2", 1000000, 10.0, 0.05, 30.0, MotorControl::kSpeedCommand, 1};
const ModelDefaults kUnknownModel{"unknown", 115200, 10.0, 0.15, 12.0, MotorControl::kDtr, 0};

}  // namespace

std::vector<uint8_t> EncodeRequest(uint8_t command, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> bytes = {kRequestSync, command};
  if (payload.empty()) return bytes;
  bytes.push_back(static_cast<uint8_t>(payload.size()));
  bytes.insert(bytes.end(), payload.begin(), payload.end());
  uint8_t checksum = 0;
  for (const uint8_t b : bytes) checksum ^= b;
  bytes.push_back(checksum);
  return bytes;
}

std::vector<uint8_t> EncodeExpressScanRequest(uint8_t working_mode) {
  return EncodeRequest(command::kExpressScan, {working_mode, 0, 0, 0, 0});
}

std::vector<uint8_t> EncodeMotorSpeedRequest(uint16_t rpm) {
  return EncodeRequest(command::kMotorSpeedCtrl,
                       {static_cast<uint8_t>(rpm & 0xFF), static_cast<uint8_t>(rpm >> 8)});
}

std::optional<ResponseDescriptor> ParseDescriptor(const uint8_t* bytes) {
  if (bytes[0] != kResponseSync1 || bytes[1] != kResponseSync2) return std::nullopt;
  const uint32_t word = static_cast<uint32_t>(bytes[2]) | (static_cast<uint32_t>(bytes[3]) << 8) |
                        (static_cast<uint32_t>(bytes[4]) << 16) |
                        (static_cast<uint32_t>(bytes[5]) << 24);
  ResponseDescriptor d;
  d.length = word & 0x3FFFFFFFu;
  d.send_mode = static_cast<SendMode>(word >> 30);
  d.data_type = bytes[6];
  return d;
}

std::vector<uint8_t> EncodeDescriptor(const ResponseDescriptor& d) {
  const uint32_t word = (d.length & 0x3FFFFFFFu) | (static_cast<uint32_t>(d.send_mode) << 30);
  return {kResponseSync1,
          kResponseSync2,
          static_cast<uint8_t>(word),
          static_cast<uint8_t>(word >> 8),
          static_cast<uint8_t>(word >> 16),
          static_cast<uint8_t>(word >> 24),
          d.data_type};
}

std::string DeviceInfo::SerialText() const {
  std::string text;
  char hex[3];
  for (const uint8_t b : serial) {
    std::snprintf(hex, sizeof(hex), "%02X", b);
    text += hex;
  }
  return text;
}

std::string DeviceInfo::FirmwareText() const {
  char text[16];
  std::snprintf(text, sizeof(text), "%u.%02u", firmware_major, firmware_minor);
  return text;
}

std::optional<DeviceInfo> ParseDeviceInfo(const uint8_t* data, std::size_t size) {
  if (size < kDeviceInfoSize) return std::nullopt;
  DeviceInfo info;
  info.model = data[0];
  info.firmware_minor = data[1];  // firmware_version: minor in the low byte
  info.firmware_major = data[2];
  info.hardware = data[3];
  for (std::size_t i = 0; i < info.serial.size(); ++i) info.serial[i] = data[4 + i];
  return info;
}

std::optional<DeviceHealth> ParseDeviceHealth(const uint8_t* data, std::size_t size) {
  if (size < kDeviceHealthSize || data[0] > 2) return std::nullopt;
  DeviceHealth health;
  health.status = static_cast<HealthStatus>(data[0]);
  health.error_code = U16(data + 1);
  return health;
}

const char* HealthStatusName(HealthStatus status) {
  switch (status) {
    case HealthStatus::kGood: return "good";
    case HealthStatus::kWarning: return "warning";
    case HealthStatus::kError: return "error";
  }
  return "?";
}

std::optional<SampleRate> ParseSampleRate(const uint8_t* data, std::size_t size) {
  if (size < kSampleRateSize) return std::nullopt;
  SampleRate rate;
  rate.standard_us = U16(data);
  rate.express_us = U16(data + 2);
  if (rate.standard_us == 0 || rate.express_us == 0) return std::nullopt;
  return rate;
}

const ModelDefaults& DefaultsFor(Model model) {
  switch (model) {
    case Model::kA1: return kA1;
    case Model::kA2: return kA2;
    case Model::kA3: return kA3;
    case Model::kS1: return kS1;
    case Model::kS2: return kS2;
    case Model::kUnknown: break;
  }
  return kUnknownModel;
}

Model ModelFromInfoByte(uint8_t model_byte) {
  switch (model_byte >> 4) {
    case 1: return Model::kA1;
    case 2: return Model::kA2;
    case 3: return Model::kA3;
    case 6: return Model::kS1;
    case 7: return Model::kS2;
    default: return Model::kUnknown;
  }
}

std::optional<Model> ParseModelName(const std::string& name) {
  for (const Model m : {Model::kA1, Model::kA2, Model::kA3, Model::kS1, Model::kS2}) {
    if (name == DefaultsFor(m).name) return m;
  }
  return std::nullopt;
}

const char* ModelName(Model model) { return DefaultsFor(model).name; }

std::optional<PacketFormat> PacketFormatForAnswer(uint8_t data_type) {
  switch (data_type) {
    case answer::kMeasurement: return PacketFormat::kStandardNodes;
    case answer::kCapsuled: return PacketFormat::kLegacyCapsules;
    case answer::kDenseCapsuled: return PacketFormat::kDenseCapsules;
    default: return std::nullopt;
  }
}

const char* PacketFormatName(PacketFormat format) {
  switch (format) {
    case PacketFormat::kStandardNodes: return "standard nodes";
    case PacketFormat::kLegacyCapsules: return "express capsules";
    case PacketFormat::kDenseCapsules: return "dense capsules";
  }
  return "?";
}

double CabinAngleCompensationDeg(uint8_t six_bits) {
  const double magnitude_deg = (six_bits & 0x1F) / 8.0;
  return (six_bits & 0x20) ? -magnitude_deg : magnitude_deg;
}

ScanStreamParser::ScanStreamParser(PacketFormat format) : format_(format) {}

std::size_t ScanStreamParser::PacketSize() const {
  return format_ == PacketFormat::kStandardNodes ? kNodeSize : kCapsuleSize;
}

int ScanStreamParser::SamplesPerPacket() const {
  switch (format_) {
    case PacketFormat::kStandardNodes: return 1;
    case PacketFormat::kLegacyCapsules: return 32;
    case PacketFormat::kDenseCapsules: return 40;
  }
  return 1;
}

void ScanStreamParser::Reset() {
  buffer_.clear();
  buffer_offset_ = stream_offset_;
  skipped_since_packet_ = 0;
  in_bad_stretch_ = false;
  cached_.reset();
  previous_raw_angle_deg_ = -1.0;
}

void ScanStreamParser::Feed(const uint8_t* data, std::size_t size, std::vector<ScanSample>* out) {
  buffer_.insert(buffer_.end(), data, data + size);
  stream_offset_ += size;
  for (;;) {
    const bool took = format_ == PacketFormat::kStandardNodes ? TakeNode(out) : TakeCapsule(out);
    if (!took) break;
  }
}

void ScanStreamParser::Discard(std::size_t count) {
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(count));
  buffer_offset_ += count;
  discarded_bytes_ += static_cast<int64_t>(count);
  skipped_since_packet_ += count;
}

// Packets lost in the skipped bytes still took measurement time: keep slots counting.
void ScanStreamParser::AccountLostPackets() {
  const auto lost = static_cast<uint64_t>(
      std::llround(static_cast<double>(skipped_since_packet_) / PacketSize()));
  next_slot_ += lost * static_cast<uint64_t>(SamplesPerPacket());
  skipped_since_packet_ = 0;
}

bool ScanStreamParser::TakeNode(std::vector<ScanSample>* out) {
  if (buffer_.size() < kNodeSize) return false;
  const uint8_t* p = buffer_.data();
  const bool start = p[0] & 0x01;
  const bool inverse_start = p[0] & 0x02;
  const bool check_bit = p[1] & 0x01;
  const uint16_t angle_q6 = static_cast<uint16_t>((p[1] >> 1) | (p[2] << 7));
  // Start bit and its inverse must differ, the check bit is 1, the angle is below 360 degrees.
  if (start == inverse_start || !check_bit || angle_q6 >= 360 * 64) {
    Discard(1);
    return true;
  }
  AccountLostPackets();
  ScanSample s;
  s.angle_cw_deg = angle_q6 / 64.0;
  s.distance_m = U16(p + 3) / 4.0 / 1000.0;
  s.quality = p[0] >> 2;
  s.start_of_revolution = start;
  s.packet_end_offset = buffer_offset_ + kNodeSize;
  s.packet_size = kNodeSize;
  s.samples_after_in_packet = 0;
  s.slot = next_slot_++;
  out->push_back(s);
  buffer_.erase(buffer_.begin(), buffer_.begin() + kNodeSize);
  buffer_offset_ += kNodeSize;
  ++packets_;
  return true;
}

bool ScanStreamParser::TakeCapsule(std::vector<ScanSample>* out) {
  if (buffer_.size() < 2) return false;
  const uint8_t* p = buffer_.data();
  if ((p[0] >> 4) != 0xA || (p[1] >> 4) != 0x5) {
    Discard(1);
    return true;
  }
  if (buffer_.size() < kCapsuleSize) return false;
  uint8_t checksum = 0;
  for (std::size_t i = 2; i < kCapsuleSize; ++i) checksum ^= p[i];
  const uint8_t sent_checksum = static_cast<uint8_t>((p[0] & 0x0F) | ((p[1] & 0x0F) << 4));
  if (checksum != sent_checksum) {
    // One error per bad stretch: the bytes inside a corrupt capsule are tried as starts too.
    if (!in_bad_stretch_) ++checksum_errors_;
    in_bad_stretch_ = true;
    Discard(1);
    return true;
  }
  in_bad_stretch_ = false;
  ++packets_;
  Capsule capsule;
  std::copy(p, p + kCapsuleSize, capsule.bytes.begin());
  const uint16_t angle_word = U16(p + 2);
  capsule.start_angle_q6 = angle_word & 0x7FFF;
  capsule.start_flag = angle_word & 0x8000;
  capsule.end_offset = buffer_offset_ + kCapsuleSize;
  const int lost =
      static_cast<int>(std::llround(static_cast<double>(skipped_since_packet_) / kCapsuleSize));
  AccountLostPackets();
  capsule.first_slot = next_slot_;
  next_slot_ += static_cast<uint64_t>(SamplesPerPacket());
  buffer_.erase(buffer_.begin(), buffer_.begin() + kCapsuleSize);
  buffer_offset_ += kCapsuleSize;

  if (capsule.start_flag) {
    // S = 1: the device (re)started; the cached capsule belongs to no sequence with this one.
    cached_.reset();
    previous_raw_angle_deg_ = -1.0;
  } else if (cached_ && lost <= 1) {
    // One lost capsule in between: interpolate the cached one over the two-capsule span.
    DecodeCached(capsule.start_angle_q6, 1 + lost, out);
  }
  // More lost: the cached capsule is dropped; the raw angle still detects the next wrap.
  cached_ = capsule;
  return true;
}

void ScanStreamParser::DecodeCached(uint16_t next_start_angle_q6, int capsules_spanned,
                                    std::vector<ScanSample>* out) {
  const Capsule& c = *cached_;
  const int count = SamplesPerPacket();
  const double start_deg = c.start_angle_q6 / 64.0;
  const double next_deg = next_start_angle_q6 / 64.0;
  // AngleDiff of the protocol document: the next start angle, unwrapped past 360.
  const double diff_deg =
      start_deg <= next_deg ? next_deg - start_deg : 360.0 + next_deg - start_deg;
  const double step_deg = diff_deg / (count * capsules_spanned);
  for (int k = 0; k < count; ++k) {
    const double raw_deg = std::fmod(start_deg + step_deg * k, 360.0);
    double angle_deg = raw_deg;
    uint16_t distance_mm = 0;
    if (format_ == PacketFormat::kLegacyCapsules) {
      const uint8_t* cabin = c.bytes.data() + 4 + 5 * (k / 2);
      const uint16_t word = U16(cabin + (k % 2 == 0 ? 0 : 2));
      const uint8_t low_nibble = k % 2 == 0 ? (cabin[4] & 0x0F) : (cabin[4] >> 4);
      distance_mm = word >> 2;
      const uint8_t compensation = static_cast<uint8_t>(((word & 0x3) << 4) | low_nibble);
      // theta_k = omega_i + AngleDiff / 32 * k - dtheta_k
      angle_deg = raw_deg - CabinAngleCompensationDeg(compensation);
      angle_deg = std::fmod(angle_deg + 360.0, 360.0);
    } else {
      distance_mm = U16(c.bytes.data() + 4 + 2 * k);
    }
    ScanSample s;
    s.angle_cw_deg = angle_deg;
    s.distance_m = distance_mm / 1000.0;
    // A new revolution starts at the first sample whose raw angle is below its predecessor's.
    s.start_of_revolution = previous_raw_angle_deg_ >= 0.0 && raw_deg < previous_raw_angle_deg_;
    previous_raw_angle_deg_ = raw_deg;
    s.packet_end_offset = c.end_offset;
    s.packet_size = kCapsuleSize;
    s.samples_after_in_packet = static_cast<uint32_t>(count - 1 - k);
    s.slot = c.first_slot + static_cast<uint64_t>(k);
    out->push_back(s);
  }
}

}  // namespace aslam::rplidar
