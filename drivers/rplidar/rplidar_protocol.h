#pragma once

// The Slamtec RPLIDAR serial protocol, pure (no I/O): request encoding, response
// parsing and a streaming decoder of measurement packets. Written from Slamtec's
// "RPLIDAR Interface Protocol and Application Notes" (LR001, rev 2.x) and checked
// against the public rplidar_sdk (sl_lidar_cmd.h, sl_lidar_protocol.h).
//
// Byte order is little-endian throughout. Angles from the device are degrees
// CLOCKWISE from the sensor's front, as the document defines them; converting
// to the robot's counter-clockwise convention is the driver's job.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace aslam::rplidar {

// ---- Requests: A5 CMD, or A5 CMD SIZE PAYLOAD... CHECKSUM (XOR of every byte before it).
inline constexpr uint8_t kRequestSync = 0xA5;
inline constexpr uint8_t kResponseSync1 = 0xA5;
inline constexpr uint8_t kResponseSync2 = 0x5A;

namespace command {
inline constexpr uint8_t kStop = 0x25;
inline constexpr uint8_t kReset = 0x40;
inline constexpr uint8_t kScan = 0x20;
inline constexpr uint8_t kForceScan = 0x21;
inline constexpr uint8_t kExpressScan = 0x82;  // firmware >= 1.17
inline constexpr uint8_t kGetInfo = 0x50;
inline constexpr uint8_t kGetHealth = 0x52;
inline constexpr uint8_t kGetSampleRate = 0x59;   // firmware >= 1.17
inline constexpr uint8_t kGetLidarConf = 0x84;    // firmware >= 1.24: scan modes and their traits
inline constexpr uint8_t kMotorSpeedCtrl = 0xA8;  // S-series: motor speed in rpm
}  // namespace command

// Data types of response descriptors.
namespace answer {
inline constexpr uint8_t kDeviceInfo = 0x04;
inline constexpr uint8_t kDeviceHealth = 0x06;
inline constexpr uint8_t kSampleRate = 0x15;
inline constexpr uint8_t kLidarConf = 0x20;
inline constexpr uint8_t kMeasurement = 0x81;    // SCAN: 5-byte nodes
inline constexpr uint8_t kCapsuled = 0x82;       // EXPRESS_SCAN legacy: 84-byte capsules
inline constexpr uint8_t kUltraCapsuled = 0x84;  // A-series Boost/Sensitivity/Stability: 132 bytes
inline constexpr uint8_t kDenseCapsuled = 0x85;  // S-series DenseBoost: 84-byte capsules
}  // namespace answer

inline constexpr std::size_t kDescriptorSize = 7;
inline constexpr std::size_t kDeviceInfoSize = 20;
inline constexpr std::size_t kDeviceHealthSize = 3;
inline constexpr std::size_t kSampleRateSize = 4;
inline constexpr std::size_t kNodeSize = 5;
inline constexpr std::size_t kCapsuleSize = 84;        // legacy and dense alike
inline constexpr std::size_t kUltraCapsuleSize = 132;  // 4 header bytes, 32 cabins of 4 bytes
inline constexpr std::size_t kUltraCabins = 32;

// GET_LIDAR_CONF configuration types (the request's first 4 payload bytes, echoed in the answer).
namespace lidar_conf {
inline constexpr uint32_t kScanModeCount = 0x70;        // u16: modes, ids 0..count-1
inline constexpr uint32_t kScanModeUsPerSample = 0x71;  // u32 Q8 microseconds, per mode id
inline constexpr uint32_t kScanModeMaxDistance = 0x74;  // u32 Q8 meters, per mode id
inline constexpr uint32_t kScanModeAnswerType = 0x75;   // u8 scan answer data type, per mode id
inline constexpr uint32_t kScanModeTypical = 0x7C;      // u16: the recommended mode id
inline constexpr uint32_t kScanModeName = 0x7F;         // text, per mode id
}  // namespace lidar_conf

// A request: `command` alone when `payload` is empty, else with size, payload and checksum.
std::vector<uint8_t> EncodeRequest(uint8_t command, const std::vector<uint8_t>& payload = {});
// EXPRESS_SCAN with its 5-byte payload: working mode, then flags and parameter (zero).
std::vector<uint8_t> EncodeExpressScanRequest(uint8_t working_mode);
// MOTOR_SPEED_CTRL (0xA8) with the speed in rpm (0 stops the motor).
std::vector<uint8_t> EncodeMotorSpeedRequest(uint16_t rpm);
// GET_LIDAR_CONF: the 32-bit type, then for per-mode types the 16-bit scan mode id.
std::vector<uint8_t> EncodeGetLidarConfRequest(uint32_t type,
                                               std::optional<uint16_t> scan_mode_id = std::nullopt);

// ---- Responses.
enum class SendMode : uint8_t { kSingle = 0, kMultiple = 1 };

struct ResponseDescriptor {
  uint32_t length = 0;  // bytes per response (30 bits)
  SendMode send_mode = SendMode::kSingle;
  uint8_t data_type = 0;
};
// The 7 descriptor bytes A5 5A LEN(30 bits)+MODE(2 bits) TYPE; nullopt without the sync bytes.
std::optional<ResponseDescriptor> ParseDescriptor(const uint8_t* bytes);
std::vector<uint8_t> EncodeDescriptor(const ResponseDescriptor& descriptor);

struct DeviceInfo {
  uint8_t model = 0;  // high nibble: series (1 A1, 2 A2, 3 A3, 6 S1, 7 S2), low: sub-model
  uint8_t firmware_major = 0;
  uint8_t firmware_minor = 0;
  uint8_t hardware = 0;
  std::array<uint8_t, 16> serial{};
  std::string SerialText() const;    // 32 hex digits, as Slamtec's tools print it
  std::string FirmwareText() const;  // "1.29"
  int FirmwareNumber() const { return firmware_major * 256 + firmware_minor; }
};
std::optional<DeviceInfo> ParseDeviceInfo(const uint8_t* data, std::size_t size);

enum class HealthStatus : uint8_t { kGood = 0, kWarning = 1, kError = 2 };
struct DeviceHealth {
  HealthStatus status = HealthStatus::kGood;
  uint16_t error_code = 0;
};
std::optional<DeviceHealth> ParseDeviceHealth(const uint8_t* data, std::size_t size);
const char* HealthStatusName(HealthStatus status);

// Time of one measurement in SCAN and in EXPRESS_SCAN mode.
struct SampleRate {
  uint16_t standard_us = 0;
  uint16_t express_us = 0;
};
std::optional<SampleRate> ParseSampleRate(const uint8_t* data, std::size_t size);

// GET_LIDAR_CONF answer data (type 0x20): the echoed type, then the value. Returns the value;
// nullopt when the echo is not `type` or no value follows it.
std::optional<std::vector<uint8_t>> ParseLidarConfValue(uint32_t type, const uint8_t* data,
                                                        std::size_t size);
// The value's first `bytes` bytes as a little-endian unsigned; nullopt when it is shorter.
std::optional<uint32_t> LidarConfUnsigned(const std::vector<uint8_t>& value, std::size_t bytes);
// A 32-bit Q8 fixed-point value (microseconds per sample, meters).
std::optional<double> LidarConfQ8(const std::vector<uint8_t>& value);
// A text value, up to its first NUL.
std::string LidarConfText(const std::vector<uint8_t>& value);

// A scan mode as GET_LIDAR_CONF describes it; `id` is EXPRESS_SCAN's working mode.
struct ScanMode {
  uint16_t id = 0;
  std::string name;  // "Standard", "Express", "Boost", "Sensitivity", "Stability", "DenseBoost"
  double us_per_sample = 0.0;
  double max_distance_m = 0.0;
  uint8_t answer_type = 0;  // 0x81 nodes, 0x82 legacy, 0x84 ultra, 0x85 dense capsules
};
// Case-insensitive and blind to spaces, '-' and '_': "DenseBoost" matches "denseboost".
bool ScanModeNameMatches(const std::string& device_name, const std::string& wanted);
// Slamtec's scan mode names, lower case: what scan_mode accepts besides standard/express/auto.
const std::vector<std::string>& KnownScanModeNames();

// ---- Models.
enum class Model { kA1, kA2, kA3, kS1, kS2, kUnknown };

enum class MotorControl {
  kDtr,          // A1/A2/A3 on Slamtec's USB adapter: DTR drives the motor enable (MOTOCTL)
  kSpeedCommand  // S1/S2: MOTOR_SPEED_CTRL (0xA8) with rpm
};

struct ModelDefaults {
  const char* name;
  int baud;            // the serial rate the model ships with
  double rotation_hz;  // nominal scan rate, for the default beam count
  double range_min_m;
  double range_max_m;
  MotorControl motor;
  uint8_t express_working_mode;  // EXPRESS_SCAN mode: 0 legacy capsules, 1 DenseBoost on S
};
const ModelDefaults& DefaultsFor(Model model);
Model ModelFromInfoByte(uint8_t model_byte);
// "a1", "a2", "a3", "s1", "s2" -> the model; anything else -> nullopt.
std::optional<Model> ParseModelName(const std::string& name);
const char* ModelName(Model model);

// ---- Measurements.
struct ScanSample {
  double angle_cw_deg = 0.0;  // clockwise from the sensor's front, [0, 360)
  double distance_m = 0.0;    // 0 = no return
  uint8_t quality = 0;        // SCAN nodes only (0..63); capsules carry none
  bool start_of_revolution = false;
  // Stream offset just past the last byte of the packet that carried this sample.
  uint64_t packet_end_offset = 0;
  uint32_t packet_size = 0;  // bytes in that packet
  // This sample was measured this many sample periods before the packet's last one.
  uint32_t samples_after_in_packet = 0;
  // Measurement slot number: +1 per sample, including samples of packets lost to errors.
  uint64_t slot = 0;
};

enum class PacketFormat { kStandardNodes, kLegacyCapsules, kDenseCapsules, kUltraCapsules };
// The format a scan response descriptor's data type announces; nullopt for types not decoded.
std::optional<PacketFormat> PacketFormatForAnswer(uint8_t data_type);
const char* PacketFormatName(PacketFormat format);

// Decodes a measurement stream fed in arbitrary chunks. Resynchronises after garbage,
// partial packets and checksum errors (counted, never thrown).
class ScanStreamParser {
 public:
  explicit ScanStreamParser(PacketFormat format);

  // Appends the samples decoded from `size` more bytes to *out.
  void Feed(const uint8_t* data, std::size_t size, std::vector<ScanSample>* out);
  // Forgets buffered bytes and the cached capsule (after a restart of the scan).
  void Reset();

  PacketFormat format() const { return format_; }
  int64_t checksum_errors() const { return checksum_errors_; }
  int64_t discarded_bytes() const { return discarded_bytes_; }
  int64_t packets() const { return packets_; }
  uint64_t stream_offset() const { return stream_offset_; }

 private:
  struct Capsule {
    uint16_t start_angle_q6 = 0;
    bool start_flag = false;
    std::array<uint8_t, kUltraCapsuleSize> bytes{};  // the first PacketSize() are used
    uint64_t end_offset = 0;
    uint64_t first_slot = 0;
  };
  std::size_t PacketSize() const;
  int SamplesPerPacket() const;
  // Tries to take one packet at the front of the buffer: true if it consumed bytes.
  bool TakeNode(std::vector<ScanSample>* out);
  bool TakeCapsule(std::vector<ScanSample>* out);
  // Decodes the cached capsule with the start angle of the one after it and, for ultra
  // capsules, that one's first major (nullopt when a capsule was lost in between).
  void DecodeCached(uint16_t next_start_angle_q6, std::optional<uint16_t> next_first_major,
                    int capsules_spanned, std::vector<ScanSample>* out);
  void Discard(std::size_t count);
  void AccountLostPackets();

  PacketFormat format_;
  std::vector<uint8_t> buffer_;
  uint64_t stream_offset_ = 0;  // bytes fed so far
  uint64_t buffer_offset_ = 0;  // stream offset of buffer_[0]
  uint64_t next_slot_ = 0;
  std::size_t skipped_since_packet_ = 0;  // bytes discarded since the last good packet
  bool in_bad_stretch_ = false;           // counting one checksum error per bad stretch
  std::optional<Capsule> cached_;
  double previous_raw_angle_deg_ = -1.0;  // for the start-of-revolution flag of capsules
  int64_t checksum_errors_ = 0;
  int64_t discarded_bytes_ = 0;
  int64_t packets_ = 0;
};

// ---- Field codecs, shared by the parser and its tests.
// The 6-bit angle compensation of a legacy cabin, q3 degrees; the top bit is the sign.
double CabinAngleCompensationDeg(uint8_t six_bits);

// Ultra cabins (answer type 0x84), after Slamtec's rplidar_sdk (sl_lidar_cmd.h, the protocol
// document defers to it): a little-endian u32 of | predict2:10 | predict1:10 | major:12 |.
// The 12-bit major in the variable bit scale: 0..511 as is, then steps of 2 from 512 mm
// (raw 512), 4 from 2048 (raw 1280), 8 from 4096 (raw 1792), 16 from 16384 mm (raw 3328).
struct VarBitScaleValue {
  uint32_t distance_mm = 0;
  int scale_shift = 0;  // log2 of the step, which also scales the predicts based on it
};
VarBitScaleValue DecodeVarBitScale(uint16_t major12);
// The cabin's three distances (mm, 0 = no return): the major; predict1 << shift added to the
// major (or to the next cabin's major when this one is 0 and that one is not); predict2 <<
// shift added to the next cabin's major. Predicts are signed 10-bit; -512 and +511 mark a
// sample without a return, as does a negative sum. `next_major12` nullopt: the next cabin was
// lost, so samples based on it are unknown (0).
std::array<uint32_t, 3> DecodeUltraCabin(uint32_t combined, std::optional<uint16_t> next_major12);
// The mean angle offset (degrees) an ultra sample's raw angle is reduced by, from its distance:
// 7.5 below 50 mm, else 8 deg - (64 k + floor(k^3 / 98304)) / 65536 rad with
// k = floor(98361 / (4 * distance_mm)), as rplidar_sdk's _ultraCapsuleToNormal computes it.
double UltraCabinAngleOffsetDeg(uint32_t distance_mm);

}  // namespace aslam::rplidar
