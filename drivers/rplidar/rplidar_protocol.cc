#include "drivers/rplidar/rplidar_protocol.h"

#include <cctype>
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

std::vector<uint8_t> EncodeGetLidarConfRequest(uint32_t type,
                                               std::optional<uint16_t> scan_mode_id) {
  std::vector<uint8_t> payload = {static_cast<uint8_t>(type), static_cast<uint8_t>(type >> 8),
                                  static_cast<uint8_t>(type >> 16),
                                  static_cast<uint8_t>(type >> 24)};
  if (scan_mode_id) {
    payload.push_back(static_cast<uint8_t>(*scan_mode_id & 0xFF));
    payload.push_back(static_cast<uint8_t>(*scan_mode_id >> 8));
  }
  return EncodeRequest(command::kGetLidarConf, payload);
}

std::optional<std::vector<uint8_t>> ParseLidarConfValue(uint32_t type, const uint8_t* data,
                                                        std::size_t size) {
  if (size <= 4) return std::nullopt;
  const uint32_t echoed = static_cast<uint32_t>(data[0]) | (static_cast<uint32_t>(data[1]) << 8) |
                          (static_cast<uint32_t>(data[2]) << 16) |
                          (static_cast<uint32_t>(data[3]) << 24);
  if (echoed != type) return std::nullopt;
  return std::vector<uint8_t>(data + 4, data + size);
}

std::optional<uint32_t> LidarConfUnsigned(const std::vector<uint8_t>& value, std::size_t bytes) {
  if (bytes > 4 || value.size() < bytes) return std::nullopt;
  uint32_t result = 0;
  for (std::size_t i = 0; i < bytes; ++i) result |= static_cast<uint32_t>(value[i]) << (8 * i);
  return result;
}

std::optional<double> LidarConfQ8(const std::vector<uint8_t>& value) {
  const auto q8 = LidarConfUnsigned(value, 4);
  if (!q8) return std::nullopt;
  return *q8 / 256.0;
}

std::string LidarConfText(const std::vector<uint8_t>& value) {
  std::string text;
  for (const uint8_t b : value) {
    if (b == 0) break;
    text.push_back(static_cast<char>(b));
  }
  return text;
}

namespace {
std::string NormalizedModeName(const std::string& name) {
  std::string normalized;
  for (const char ch : name) {
    if (ch == ' ' || ch == '-' || ch == '_') continue;
    normalized.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
  }
  return normalized;
}
}  // namespace

bool ScanModeNameMatches(const std::string& device_name, const std::string& wanted) {
  const std::string normalized = NormalizedModeName(device_name);
  return !normalized.empty() && normalized == NormalizedModeName(wanted);
}

const std::vector<std::string>& KnownScanModeNames() {
  static const std::vector<std::string> names = {"boost", "sensitivity", "stability", "denseboost"};
  return names;
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
    case answer::kUltraCapsuled: return PacketFormat::kUltraCapsules;
    default: return std::nullopt;
  }
}

const char* PacketFormatName(PacketFormat format) {
  switch (format) {
    case PacketFormat::kStandardNodes: return "standard nodes";
    case PacketFormat::kLegacyCapsules: return "express capsules";
    case PacketFormat::kDenseCapsules: return "dense capsules";
    case PacketFormat::kUltraCapsules: return "ultra capsules";
  }
  return "?";
}

double CabinAngleCompensationDeg(uint8_t six_bits) {
  const double magnitude_deg = (six_bits & 0x1F) / 8.0;
  return (six_bits & 0x20) ? -magnitude_deg : magnitude_deg;
}

VarBitScaleValue DecodeVarBitScale(uint16_t major12) {
  struct Segment {
    uint32_t raw_start;  // first raw value of the segment
    uint32_t mm_start;   // its distance
    int shift;
  };
  static constexpr Segment kSegments[] = {
      {3328, 1u << 14, 4}, {1792, 1u << 12, 3}, {1280, 1u << 11, 2}, {512, 1u << 9, 1}, {0, 0, 0}};
  const uint32_t raw = major12 & 0xFFFu;
  for (const Segment& s : kSegments) {
    if (raw >= s.raw_start) return {s.mm_start + ((raw - s.raw_start) << s.shift), s.shift};
  }
  return {};
}

std::array<uint32_t, 3> DecodeUltraCabin(uint32_t combined, std::optional<uint16_t> next_major12) {
  const VarBitScaleValue major = DecodeVarBitScale(static_cast<uint16_t>(combined & 0xFFF));
  // Signed 10-bit fields: bits 12..21 and 22..31.
  const auto signed10 = [](uint32_t bits) {
    return static_cast<int32_t>(bits & 0x3FF) - ((bits & 0x200) ? 1024 : 0);
  };
  const int32_t predict1 = signed10(combined >> 12);
  const int32_t predict2 = signed10(combined >> 22);
  const auto predicted = [](int32_t predict, std::optional<VarBitScaleValue> base) -> uint32_t {
    if (!base || predict == -512 || predict == 511) return 0;  // the escapes: no return
    const int64_t mm = static_cast<int64_t>(base->distance_mm) +
                       static_cast<int64_t>(predict) * (int64_t{1} << base->scale_shift);
    return mm > 0 ? static_cast<uint32_t>(mm) : 0;
  };
  std::optional<VarBitScaleValue> next;
  if (next_major12) next = DecodeVarBitScale(*next_major12);
  std::optional<VarBitScaleValue> base1 = major;
  // A cabin whose major is no return predicts its second sample from the next major.
  if (major.distance_mm == 0) {
    if (!next) base1.reset();
    if (next && next->distance_mm != 0) base1 = next;
  }
  return {major.distance_mm, predicted(predict1, base1), predicted(predict2, next)};
}

double UltraCabinAngleOffsetDeg(uint32_t distance_mm) {
  const uint64_t distance_q2 = uint64_t{distance_mm} * 4;
  if (distance_q2 < 50 * 4) return 7.5;
  const uint64_t k = 98361 / distance_q2;
  const double offset_rad =
      8.0 * M_PI / 180.0 - static_cast<double>(64 * k + (k * k * k) / 98304) / 65536.0;
  return offset_rad * 180.0 / M_PI;
}

ScanStreamParser::ScanStreamParser(PacketFormat format) : format_(format) {}

std::size_t ScanStreamParser::PacketSize() const {
  switch (format_) {
    case PacketFormat::kStandardNodes: return kNodeSize;
    case PacketFormat::kLegacyCapsules:
    case PacketFormat::kDenseCapsules: return kCapsuleSize;
    case PacketFormat::kUltraCapsules: return kUltraCapsuleSize;
  }
  return kCapsuleSize;
}

int ScanStreamParser::SamplesPerPacket() const {
  switch (format_) {
    case PacketFormat::kStandardNodes: return 1;
    case PacketFormat::kLegacyCapsules: return 32;
    case PacketFormat::kDenseCapsules: return 40;
    case PacketFormat::kUltraCapsules: return 3 * static_cast<int>(kUltraCabins);
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
  const std::size_t size = PacketSize();
  if (buffer_.size() < size) return false;
  uint8_t checksum = 0;
  for (std::size_t i = 2; i < size; ++i) checksum ^= p[i];
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
  std::copy(p, p + size, capsule.bytes.begin());
  const uint16_t angle_word = U16(p + 2);
  capsule.start_angle_q6 = angle_word & 0x7FFF;
  capsule.start_flag = angle_word & 0x8000;
  capsule.end_offset = buffer_offset_ + size;
  const int lost =
      static_cast<int>(std::llround(static_cast<double>(skipped_since_packet_) / size));
  AccountLostPackets();
  capsule.first_slot = next_slot_;
  next_slot_ += static_cast<uint64_t>(SamplesPerPacket());
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(size));
  buffer_offset_ += size;

  if (capsule.start_flag) {
    // S = 1: the device (re)started; the cached capsule belongs to no sequence with this one.
    cached_.reset();
    previous_raw_angle_deg_ = -1.0;
  } else if (cached_ && lost <= 1) {
    // One lost capsule in between: interpolate the cached one over the two-capsule span.
    std::optional<uint16_t> next_first_major;
    if (lost == 0) next_first_major = static_cast<uint16_t>(U16(capsule.bytes.data() + 4) & 0xFFF);
    DecodeCached(capsule.start_angle_q6, next_first_major, 1 + lost, out);
  }
  // More lost: the cached capsule is dropped; the raw angle still detects the next wrap.
  cached_ = capsule;
  return true;
}

void ScanStreamParser::DecodeCached(uint16_t next_start_angle_q6,
                                    std::optional<uint16_t> next_first_major, int capsules_spanned,
                                    std::vector<ScanSample>* out) {
  const Capsule& c = *cached_;
  const int count = SamplesPerPacket();
  const uint8_t* body = c.bytes.data() + 4;
  // Distances and the angle each sample's raw angle is reduced by (theta = raw - offset).
  std::vector<uint32_t> distance_mm(static_cast<std::size_t>(count), 0);
  std::vector<double> offset_deg(static_cast<std::size_t>(count), 0.0);
  if (format_ == PacketFormat::kLegacyCapsules) {
    for (int k = 0; k < count; ++k) {
      const uint8_t* cabin = body + 5 * (k / 2);
      const uint16_t word = U16(cabin + (k % 2 == 0 ? 0 : 2));
      const uint8_t low_nibble = k % 2 == 0 ? (cabin[4] & 0x0F) : (cabin[4] >> 4);
      distance_mm[k] = word >> 2;
      const uint8_t compensation = static_cast<uint8_t>(((word & 0x3) << 4) | low_nibble);
      offset_deg[k] = CabinAngleCompensationDeg(compensation);
    }
  } else if (format_ == PacketFormat::kDenseCapsules) {
    for (int k = 0; k < count; ++k) distance_mm[k] = U16(body + 2 * k);
  } else {
    const auto combined = [body](std::size_t cabin) {
      const uint8_t* b = body + 4 * cabin;
      return static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) |
             (static_cast<uint32_t>(b[2]) << 16) | (static_cast<uint32_t>(b[3]) << 24);
    };
    for (std::size_t cabin = 0; cabin < kUltraCabins; ++cabin) {
      std::optional<uint16_t> next_major = next_first_major;
      if (cabin + 1 < kUltraCabins) next_major = static_cast<uint16_t>(combined(cabin + 1) & 0xFFF);
      const std::array<uint32_t, 3> d = DecodeUltraCabin(combined(cabin), next_major);
      for (std::size_t m = 0; m < 3; ++m) {
        distance_mm[3 * cabin + m] = d[m];
        offset_deg[3 * cabin + m] = UltraCabinAngleOffsetDeg(d[m]);
      }
    }
  }
  const double start_deg = c.start_angle_q6 / 64.0;
  const double next_deg = next_start_angle_q6 / 64.0;
  // AngleDiff of the protocol document: the next start angle, unwrapped past 360.
  const double diff_deg =
      start_deg <= next_deg ? next_deg - start_deg : 360.0 + next_deg - start_deg;
  const double step_deg = diff_deg / (count * capsules_spanned);
  for (int k = 0; k < count; ++k) {
    const double raw_deg = std::fmod(start_deg + step_deg * k, 360.0);
    ScanSample s;
    // theta_k = omega_i + AngleDiff / n * k - dtheta_k
    double angle_deg = raw_deg - offset_deg[k];
    if (angle_deg < 0.0) angle_deg += 360.0;
    if (angle_deg >= 360.0) angle_deg -= 360.0;
    s.angle_cw_deg = angle_deg;
    s.distance_m = distance_mm[k] / 1000.0;
    // A new revolution starts at the first sample whose raw angle is below its predecessor's.
    s.start_of_revolution = previous_raw_angle_deg_ >= 0.0 && raw_deg < previous_raw_angle_deg_;
    previous_raw_angle_deg_ = raw_deg;
    s.packet_end_offset = c.end_offset;
    s.packet_size = static_cast<uint32_t>(PacketSize());
    s.samples_after_in_packet = static_cast<uint32_t>(count - 1 - k);
    s.slot = c.first_slot + static_cast<uint64_t>(k);
    out->push_back(s);
  }
}

}  // namespace aslam::rplidar
