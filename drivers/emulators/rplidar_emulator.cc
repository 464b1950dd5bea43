#include "drivers/emulators/rplidar_emulator.h"

#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "drivers/io/host_clock.h"

namespace aslam {
namespace {

double NowS() { return HostClockUtime() * 1e-6; }

void PutU16(std::vector<uint8_t>* bytes, unsigned value) {
  bytes->push_back(static_cast<uint8_t>(value & 0xFF));
  bytes->push_back(static_cast<uint8_t>((value >> 8) & 0xFF));
}

void PutU32(std::vector<uint8_t>* bytes, uint32_t value) {
  PutU16(bytes, value & 0xFFFF);
  PutU16(bytes, value >> 16);
}

// Ultra cabin majors in the variable bit scale of Slamtec's rplidar_sdk (sl_lidar_cmd.h):
// distances from 512, 2048, 4096 and 16384 mm are kept in steps of 2, 4, 8 and 16 mm, under
// codes counting on from 512, 1280, 1792 and 3328; below 512 mm the code is the distance.
struct ScaleBand {
  uint32_t from_mm;
  uint32_t from_code;
  int step_log2;
};
constexpr ScaleBand kScaleBands[] = {
    {16384, 3328, 4}, {4096, 1792, 3}, {2048, 1280, 2}, {512, 512, 1}, {0, 0, 0}};
constexpr uint32_t kUltraMaxMm = 16384 + (4095 - 3328) * 16;  // the largest 12-bit code

struct Major {
  uint32_t code = 0;
  uint32_t mm = 0;  // what the code stands for
  int step_log2 = 0;
};

Major MajorOfCode(uint32_t code) {
  for (const ScaleBand& band : kScaleBands) {
    if (code >= band.from_code) {
      return {code, band.from_mm + ((code - band.from_code) << band.step_log2), band.step_log2};
    }
  }
  return {};
}

Major MajorOfDistance(uint32_t mm) {
  if (mm == 0 || mm > kUltraMaxMm) return {};  // code 0: no return
  for (const ScaleBand& band : kScaleBands) {
    if (mm >= band.from_mm) {
      const double steps = std::round((mm - band.from_mm) / std::ldexp(1.0, band.step_log2));
      return MajorOfCode(std::min<uint32_t>(4095, band.from_code + static_cast<uint32_t>(steps)));
    }
  }
  return {};
}

// A 10-bit predict: the distance less the base, in the base's steps; +511 (an escape the SDK
// reads as no return) when there is no return or the difference does not fit.
uint32_t PredictBits(uint32_t mm, const Major& base) {
  constexpr uint32_t kNoReturn = 0x1FF;
  if (mm == 0 || mm > kUltraMaxMm) return kNoReturn;
  const double step = std::ldexp(1.0, base.step_log2);
  const double steps = std::round((static_cast<double>(mm) - base.mm) / step);
  if (steps < -511 || steps > 510 || base.mm + steps * step <= 0) return kNoReturn;
  return static_cast<uint32_t>(static_cast<int>(steps)) & 0x3FF;
}

// The SDK's mean angle offset of ultra samples (degrees subtracted from the raw angle):
// 7.5 deg under 50 mm, else 8 deg less (64 k + k^3 / 98304) / 65536 rad, k = 98361 / (4 mm),
// in integer divisions.
double UltraOffsetDeg(uint32_t mm) {
  if (mm < 50) return 7.5;
  const long k = 98361L / (4L * static_cast<long>(mm));
  const double less_rad = (64.0 * k + static_cast<double>((k * k * k) / 98304)) / 65536.0;
  return 8.0 - less_rad * 180.0 / M_PI;
}

// Angle compensation of legacy cabin samples, q3 degrees (sign and magnitude): a slow wave
// of +-2.5 deg, so that a decoder ignoring it, or reading the sign wrong, is off.
int CompensationQ3(int64_t sample) {
  return static_cast<int>(std::lround(20.0 * std::sin(2.0 * M_PI * sample / 400.0)));
}

}  // namespace

RplidarEmulatorOptions RplidarEmulatorModel(const std::string& name) {
  RplidarEmulatorOptions o;
  if (name == "a1") return o;  // an A1M8: model 0x18, firmware 1.29, 508/254 us, 5.5 Hz
  if (name == "a2") {
    o.model_byte = 0x28;
    o.firmware_minor = 24;
    o.hardware = 5;
    o.standard_sample_us = 500;  // 2 k samples/s
    o.express_sample_us = 250;   // 4 k samples/s
    o.rotation_hz = 10.0;
    o.boot_banner = "RP LIDAR System.\r\nFirmware Ver 1.24 - rtm, HW Ver 5\r\nModel: 28\r\n";
    return o;
  }
  if (name == "a3") {
    o.model_byte = 0x31;
    o.firmware_minor = 26;
    o.hardware = 6;
    o.standard_sample_us = 250;  // 4 k samples/s
    o.express_sample_us = 126;   // 7.9 k samples/s
    o.rotation_hz = 10.0;
    o.baud = 256000;
    o.boot_banner = "RP LIDAR System.\r\nFirmware Ver 1.26 - rtm, HW Ver 6\r\nModel: 31\r\n";
    // An A3M1's list: 4 k Standard, 8 k Express, 16 k Boost and Sensitivity, 10 k Stability.
    o.scan_modes = {{"Standard", 250.0, 16.0, 0x81},
                    {"Express", 126.0, 16.0, 0x82},
                    {"Boost", 62.5, 25.0, 0x84},
                    {"Sensitivity", 62.5, 25.0, 0x84},
                    {"Stability", 100.0, 25.0, 0x84}};
    o.typical_scan_mode = 3;  // Sensitivity
    return o;
  }
  if (name == "s1" || name == "s2") {
    o.model_byte = name == "s1" ? 0x61 : 0x71;
    o.firmware_minor = name == "s1" ? 28 : 2;
    o.hardware = 18;
    o.standard_sample_us = name == "s1" ? 244 : 125;
    o.express_sample_us = name == "s1" ? 108 : 31;  // DenseBoost: 9.2 k / 32 k samples/s
    o.dense_express = true;
    o.rotation_hz = 10.0;
    o.baud = name == "s1" ? 256000 : 1000000;
    o.boot_banner.clear();  // S-series say nothing after a reset
    return o;
  }
  throw std::invalid_argument("RplidarEmulatorModel: unknown model " + name);
}

RplidarEmulator::RplidarEmulator(RplidarEmulatorOptions options)
    : options_(std::move(options)), link_(options_.link_path, "rplidar") {
  pty_ = std::make_unique<PseudoTerminal>();
  link_.PointAt(pty_->slave_path());
  thread_ = std::thread([this] { Run(); });
}

RplidarEmulator::~RplidarEmulator() {
  running_ = false;
  thread_.join();
}

void RplidarEmulator::InjectGarbage(const std::vector<uint8_t>& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_garbage_.insert(pending_garbage_.end(), bytes.begin(), bytes.end());
}

void RplidarEmulator::CorruptNextCapsule() {
  std::lock_guard<std::mutex> lock(mutex_);
  corrupt_next_capsule_ = true;
}

void RplidarEmulator::SetHealth(uint8_t status, uint16_t error_code, bool survives_reset) {
  std::lock_guard<std::mutex> lock(mutex_);
  options_.health_status = status;
  options_.health_error_code = error_code;
  options_.health_error_survives_reset = survives_reset;
}

void RplidarEmulator::ResetNow() {
  std::lock_guard<std::mutex> lock(mutex_);
  reset_requested_ = true;
}

void RplidarEmulator::Unplug() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (pty_) pty_->Close();
  pty_.reset();
  link_.Remove();
  stream_ = Stream::kNone;
  input_.clear();
}

void RplidarEmulator::Replug() {
  std::lock_guard<std::mutex> lock(mutex_);
  pty_ = std::make_unique<PseudoTerminal>();
  link_.PointAt(pty_->slave_path());
  stream_ = Stream::kNone;
  deaf_until_s_ = 0.0;
}

std::vector<uint8_t> RplidarEmulator::ReceivedBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return received_;
}

std::vector<uint8_t> RplidarEmulator::ReceivedCommands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return commands_;
}

void RplidarEmulator::Send(const std::vector<uint8_t>& bytes) {
  if (!pty_ || bytes.empty()) return;
  // A UART never blocks: what the receiver's buffer cannot take is lost.
  const ssize_t n = ::write(pty_->master_fd(), bytes.data(), bytes.size());
  (void)n;
}

void RplidarEmulator::Run() {
  while (running_) {
    std::vector<uint8_t> input;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pty_) input = pty_->Read(0);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (reset_requested_) {
        reset_requested_ = false;
        DoReset();
        input_.clear();
      }
      if (!input.empty()) HandleInput(input);
      if (!pending_garbage_.empty() && pty_) {
        Send(pending_garbage_);
        pending_garbage_.clear();
      }
      if (stream_ != Stream::kNone) StreamDue();
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
}

void RplidarEmulator::HandleInput(const std::vector<uint8_t>& bytes) {
  received_.insert(received_.end(), bytes.begin(), bytes.end());
  if (NowS() < deaf_until_s_) return;  // booting: requests are lost
  input_.insert(input_.end(), bytes.begin(), bytes.end());
  // Requests: A5 CMD, and for CMD >= 0x80: SIZE PAYLOAD CHECKSUM (XOR of all bytes before).
  std::size_t at = 0;
  while (at < input_.size()) {
    if (input_[at] != 0xA5) {
      ++at;
      continue;
    }
    if (at + 1 >= input_.size()) break;
    const uint8_t command = input_[at + 1];
    if (!(command & 0x80)) {
      at += 2;
      commands_.push_back(command);
      HandleRequest(command, {});
      if (command == 0x40) {  // rebooting: whatever followed the RESET is lost
        input_.clear();
        return;
      }
      continue;
    }
    if (at + 2 >= input_.size()) break;
    const std::size_t size = input_[at + 2];
    if (at + 3 + size + 1 > input_.size()) break;
    uint8_t checksum = 0;
    for (std::size_t i = at; i < at + 3 + size; ++i) checksum ^= input_[i];
    if (checksum != input_[at + 3 + size]) {
      at += 1;  // not a request after all
      continue;
    }
    const std::vector<uint8_t> payload(input_.begin() + static_cast<std::ptrdiff_t>(at + 3),
                                       input_.begin() + static_cast<std::ptrdiff_t>(at + 3 + size));
    at += 3 + size + 1;
    commands_.push_back(command);
    HandleRequest(command, payload);
  }
  input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(at));
}

void RplidarEmulator::HandleRequest(uint8_t command, const std::vector<uint8_t>& payload) {
  if (options_.wrong_baud) {
    // At the wrong rate every answer arrives as noise (here: never an A5 byte).
    std::vector<uint8_t> noise(24);
    for (uint8_t& b : noise) {
      noise_state_ = noise_state_ * 1103515245u + 12345u;
      b = static_cast<uint8_t>(noise_state_ >> 16);
      if (b == 0xA5) b = 0x5A;
    }
    Send(noise);
    return;
  }
  switch (command) {
    case 0x25:  // STOP
      stream_ = Stream::kNone;
      return;
    case 0x40:  // RESET
      DoReset();
      return;
    case 0x50: {  // GET_INFO: descriptor A5 5A 14 00 00 00 04, then 20 bytes
      std::vector<uint8_t> answer = {0xA5, 0x5A, 0x14, 0x00, 0x00, 0x00, 0x04};
      answer.push_back(options_.model_byte);
      answer.push_back(options_.firmware_minor);
      answer.push_back(options_.firmware_major);
      answer.push_back(options_.hardware);
      for (int i = 0; i < 16; ++i) answer.push_back(static_cast<uint8_t>(0x30 + i));
      Send(answer);
      return;
    }
    case 0x52: {  // GET_HEALTH: descriptor A5 5A 03 00 00 00 06, status, error code
      std::vector<uint8_t> answer = {0xA5, 0x5A, 0x03, 0x00, 0x00, 0x00, 0x06};
      answer.push_back(options_.health_status);
      PutU16(&answer, options_.health_error_code);
      Send(answer);
      return;
    }
    case 0x59: {  // GET_SAMPLERATE: descriptor A5 5A 04 00 00 00 15, Tstandard, Texpress
      std::vector<uint8_t> answer = {0xA5, 0x5A, 0x04, 0x00, 0x00, 0x00, 0x15};
      PutU16(&answer, options_.standard_sample_us);
      PutU16(&answer, options_.express_sample_us);
      Send(answer);
      return;
    }
    case 0x20:                                  // SCAN
    case 0x21:                                  // FORCE_SCAN
      if (options_.health_status == 2) return;  // protection stop: no measurements
      Send({0xA5, 0x5A, 0x05, 0x00, 0x00, 0x40, 0x81});
      StartStream(Stream::kStandard, options_.standard_sample_us);
      return;
    case 0x82: {  // EXPRESS_SCAN: working_mode, working_flags (16), param (16)
      if (options_.health_status == 2 || payload.size() != 5) return;
      const uint8_t working_mode = payload[0];
      if (working_mode > 0 && !options_.scan_modes.empty()) {
        if (working_mode >= options_.scan_modes.size()) return;  // no such mode: ignored
        const RplidarEmulatorScanMode& mode = options_.scan_modes[working_mode];
        switch (mode.answer_type) {
          case 0x81:
            Send({0xA5, 0x5A, 0x05, 0x00, 0x00, 0x40, 0x81});
            StartStream(Stream::kStandard, mode.us_per_sample);
            return;
          case 0x82:
          case 0x85:
            Send({0xA5, 0x5A, 0x54, 0x00, 0x00, 0x40, mode.answer_type});
            StartStream(mode.answer_type == 0x82 ? Stream::kLegacy : Stream::kDense,
                        mode.us_per_sample);
            return;
          case 0x84:  // ultra capsules: 132 bytes
            Send({0xA5, 0x5A, 0x84, 0x00, 0x00, 0x40, 0x84});
            StartStream(Stream::kUltra, mode.us_per_sample);
            return;
          default: return;
        }
      }
      if (options_.dense_express) {
        Send({0xA5, 0x5A, 0x54, 0x00, 0x00, 0x40, 0x85});
        StartStream(Stream::kDense, options_.express_sample_us);
      } else {
        Send({0xA5, 0x5A, 0x54, 0x00, 0x00, 0x40, 0x82});
        StartStream(Stream::kLegacy, options_.express_sample_us);
      }
      return;
    }
    case 0x84:  // GET_LIDAR_CONF
      AnswerLidarConf(payload);
      return;
    default:  // MOTOR_SPEED_CTRL and the rest: no answer
      return;
  }
}

void RplidarEmulator::AnswerLidarConf(const std::vector<uint8_t>& payload) {
  // Firmware before 1.24 does not know the request.
  if (options_.scan_modes.empty() || payload.size() < 4) return;
  // Request payload: type (32 bits), then for per-mode types the mode id (16 bits).
  const uint32_t type = static_cast<uint32_t>(payload[0]) | (payload[1] << 8) | (payload[2] << 16) |
                        (static_cast<uint32_t>(payload[3]) << 24);
  const unsigned id =
      payload.size() >= 6 ? static_cast<unsigned>(payload[4] | (payload[5] << 8)) : 0u;
  const RplidarEmulatorScanMode* mode =
      id < options_.scan_modes.size() ? &options_.scan_modes[id] : nullptr;
  std::vector<uint8_t> value;
  switch (type) {
    case 0x70: PutU16(&value, static_cast<unsigned>(options_.scan_modes.size())); break;
    case 0x7C: PutU16(&value, options_.typical_scan_mode); break;
    case 0x71:  // Q8 microseconds
      if (!mode) return;
      PutU32(&value, static_cast<uint32_t>(std::lround(mode->us_per_sample * 256.0)));
      break;
    case 0x74:  // Q8 meters
      if (!mode) return;
      PutU32(&value, static_cast<uint32_t>(std::lround(mode->max_distance_m * 256.0)));
      break;
    case 0x75:
      if (!mode) return;
      value.push_back(mode->answer_type);
      break;
    case 0x7F:
      if (!mode) return;
      value.assign(mode->name.begin(), mode->name.end());
      value.push_back(0);
      break;
    default: return;
  }
  std::vector<uint8_t> answer_data;
  if (options_.lidar_conf_error) {
    PutU32(&answer_data, type ^ 0x1000);  // some other entry's type, and nothing after it
  } else {
    PutU32(&answer_data, type);
    answer_data.insert(answer_data.end(), value.begin(), value.end());
  }
  // Descriptor: A5 5A, length (30 bits) with send mode 0 (single), data type 0x20.
  std::vector<uint8_t> answer = {0xA5, 0x5A};
  PutU32(&answer, static_cast<uint32_t>(answer_data.size()));
  answer.push_back(0x20);
  answer.insert(answer.end(), answer_data.begin(), answer_data.end());
  Send(answer);
}

void RplidarEmulator::DoReset() {
  ++resets_;
  stream_ = Stream::kNone;
  if (!options_.boot_banner.empty()) {
    Send(std::vector<uint8_t>(options_.boot_banner.begin(), options_.boot_banner.end()));
  }
  deaf_until_s_ = NowS() + options_.boot_time_s;
  if (!options_.health_error_survives_reset) {
    options_.health_status = 0;
    options_.health_error_code = 0;
  }
}

void RplidarEmulator::StartStream(Stream stream, double sample_us) {
  ++scans_started_;
  stream_ = stream;
  stream_period_s_ = sample_us * 1e-6;
  stream_start_s_ = NowS();
  wire_free_s_ = stream_start_s_;
  next_packet_ = 0;
  Send(options_.garbage_before_first_packet);
}

int64_t RplidarEmulator::SampleUtime(int64_t sample) const {
  return std::llround((stream_start_s_ + sample * stream_period_s_ / options_.time_scale) * 1e6);
}

double RplidarEmulator::AngleAtSampleDeg(int64_t sample) const {
  return std::fmod(
      options_.start_angle_deg + 360.0 * options_.rotation_hz * stream_period_s_ * sample, 360.0);
}

void RplidarEmulator::StreamDue() {
  int per_packet = 1, packet_bytes = 5;  // standard: a 5-byte node per sample
  if (stream_ == Stream::kLegacy) per_packet = 32, packet_bytes = 84;  // 16 cabins of 5 bytes
  if (stream_ == Stream::kDense) per_packet = 40, packet_bytes = 84;   // 40 distances of 2
  if (stream_ == Stream::kUltra) per_packet = 96, packet_bytes = 132;  // 32 cabins of 4
  const double byte_s = 10.0 / options_.baud;                          // 8N1
  const double now_s = NowS();
  // A packet goes out once its last sample is measured and the one before it has left; the
  // driver has it when its last byte has crossed the wire.
  std::vector<uint8_t> out;
  while (out.size() < 16384) {
    const double last_sample_s = SampleUtime((next_packet_ + 1) * per_packet - 1) * 1e-6;
    const double arrives_s = std::max(last_sample_s, wire_free_s_) + packet_bytes * byte_s;
    if (arrives_s > now_s) break;
    std::vector<uint8_t> packet;
    if (stream_ == Stream::kStandard) {
      packet = StandardNode(next_packet_);
    } else if (stream_ == Stream::kUltra) {
      packet = UltraCapsuleAt(next_packet_);
    } else {
      packet = CapsuleAt(next_packet_);
    }
    out.insert(out.end(), packet.begin(), packet.end());
    wire_free_s_ = arrives_s;
    ++next_packet_;
    ++packets_sent_;
  }
  Send(out);
}

std::vector<uint8_t> RplidarEmulator::StandardNode(int64_t sample) {
  // Node: [quality:6 | !S | S], [angle_q6[6:0] | C=1], angle_q6[14:7], distance_q2 (16 bits).
  const int angle_q6 = static_cast<int>(std::lround(AngleAtSampleDeg(sample) * 64.0)) % (360 * 64);
  const bool start =
      sample > 0 && AngleAtSampleDeg(sample) < AngleAtSampleDeg(sample - 1);  // passed 0 deg
  const double range_m = options_.range_m(angle_q6 / 64.0 * M_PI / 180.0, SampleUtime(sample));
  long distance_q2 = std::lround(range_m * 4000.0);
  if (distance_q2 < 0 || distance_q2 > 0xFFFF) distance_q2 = 0;
  const uint8_t quality = distance_q2 > 0 ? 47 : 0;
  std::vector<uint8_t> node;
  node.push_back(static_cast<uint8_t>((quality << 2) | (start ? 0x01 : 0x02)));
  node.push_back(static_cast<uint8_t>(((angle_q6 & 0x7F) << 1) | 0x01));
  node.push_back(static_cast<uint8_t>(angle_q6 >> 7));
  PutU16(&node, static_cast<unsigned>(distance_q2));
  return node;
}

std::vector<uint8_t> RplidarEmulator::CapsuleAt(int64_t capsule) {
  const bool dense = stream_ == Stream::kDense;
  const int per_capsule = dense ? 40 : 32;
  const int64_t first = capsule * per_capsule;
  // start_angle_q6 of this capsule and the next; samples lie between them (AngleDiff / n).
  const int start_q6 = static_cast<int>(std::lround(AngleAtSampleDeg(first) * 64.0)) % (360 * 64);
  const int next_q6 =
      static_cast<int>(std::lround(AngleAtSampleDeg(first + per_capsule) * 64.0)) % (360 * 64);
  const double start_deg = start_q6 / 64.0;
  double diff_deg = next_q6 / 64.0 - start_deg;
  if (diff_deg < 0) diff_deg += 360.0;
  std::vector<uint8_t> bytes = {0, 0};
  PutU16(&bytes, static_cast<unsigned>(start_q6) | (capsule == 0 ? 0x8000u : 0u));
  std::vector<unsigned> distance_mm(per_capsule);
  std::vector<unsigned> compensation_six(per_capsule);  // sign bit, then 5 bits of q3
  for (int k = 0; k < per_capsule; ++k) {
    const double raw_deg = start_deg + diff_deg * k / per_capsule;
    const int compensation_q3 = dense ? 0 : CompensationQ3(first + k);
    // theta_k = omega_i + AngleDiff / n * k - dtheta_k: the angle the sample was taken at.
    const double angle_deg = std::fmod(raw_deg - compensation_q3 / 8.0 + 360.0, 360.0);
    const long mm =
        std::lround(options_.range_m(angle_deg * M_PI / 180.0, SampleUtime(first + k)) * 1000.0);
    const long limit_mm = dense ? 0xFFFF : 0x3FFF;  // dense: 16 bits; legacy: 14 bits
    distance_mm[k] = mm < 0 || mm > limit_mm ? 0u : static_cast<unsigned>(mm);
    compensation_six[k] = (compensation_q3 < 0 ? 0x20u : 0u) |
                          static_cast<unsigned>(std::abs(compensation_q3) & 0x1F);
  }
  if (dense) {
    for (int k = 0; k < per_capsule; ++k) PutU16(&bytes, distance_mm[k]);
  } else {
    // Cabin of two samples: [distance1:14 | dtheta1[5:4]], [distance2:14 | dtheta2[5:4]],
    // [dtheta2[3:0] : dtheta1[3:0]].
    for (int k = 0; k < per_capsule; k += 2) {
      PutU16(&bytes, (distance_mm[k] << 2) | (compensation_six[k] >> 4));
      PutU16(&bytes, (distance_mm[k + 1] << 2) | (compensation_six[k + 1] >> 4));
      bytes.push_back(static_cast<uint8_t>((compensation_six[k] & 0x0F) |
                                           ((compensation_six[k + 1] & 0x0F) << 4)));
    }
  }
  SealCapsule(&bytes);
  return bytes;
}

void RplidarEmulator::SealCapsule(std::vector<uint8_t>* bytes) {
  // Sync nibbles A and 5 under the XOR of every byte after the first two.
  uint8_t checksum = 0;
  for (std::size_t i = 2; i < bytes->size(); ++i) checksum ^= (*bytes)[i];
  (*bytes)[0] = static_cast<uint8_t>(0xA0 | (checksum & 0x0F));
  (*bytes)[1] = static_cast<uint8_t>(0x50 | (checksum >> 4));
  if (corrupt_next_capsule_) {
    corrupt_next_capsule_ = false;
    (*bytes)[40] ^= 0x10;  // after the checksum: the receiver must reject this capsule
  }
}

int RplidarEmulator::UltraStartQ6(int64_t capsule) const {
  return static_cast<int>(std::lround(AngleAtSampleDeg(capsule * 96) * 64.0)) % (360 * 64);
}

uint32_t RplidarEmulator::UltraSampleMm(int64_t capsule, int sample) const {
  // Raw angles step evenly from this capsule's start angle to the next one's.
  const double start_deg = UltraStartQ6(capsule) / 64.0;
  double diff_deg = UltraStartQ6(capsule + 1) / 64.0 - start_deg;
  if (diff_deg < 0) diff_deg += 360.0;
  const double raw_deg = start_deg + diff_deg * sample / 96.0;
  // The sample lies at raw - offset(distance): settle the distance there by iteration.
  long mm = 0;
  double offset_deg = 8.0;
  for (int i = 0; i < 4; ++i) {
    const double angle_deg = std::fmod(raw_deg - offset_deg + 720.0, 360.0);
    mm = std::lround(
        options_.range_m(angle_deg * M_PI / 180.0, SampleUtime(capsule * 96 + sample)) * 1000.0);
    if (mm <= 0 || mm > static_cast<long>(kUltraMaxMm)) return 0;
    offset_deg = UltraOffsetDeg(static_cast<uint32_t>(mm));
  }
  return static_cast<uint32_t>(mm);
}

std::vector<uint8_t> RplidarEmulator::UltraCapsuleAt(int64_t capsule) {
  std::vector<uint8_t> bytes = {0, 0};
  PutU16(&bytes, static_cast<unsigned>(UltraStartQ6(capsule)) | (capsule == 0 ? 0x8000u : 0u));
  // 96 samples, and the next capsule's first: the last cabin predicts from its major.
  std::vector<uint32_t> mm(97);
  for (int k = 0; k < 96; ++k) mm[k] = UltraSampleMm(capsule, k);
  mm[96] = UltraSampleMm(capsule + 1, 0);
  for (int cabin = 0; cabin < 32; ++cabin) {
    const Major major = MajorOfDistance(mm[3 * cabin]);
    const Major next = MajorOfDistance(mm[3 * cabin + 3]);
    // A major without a return lends its first predict the next major as base.
    const Major& base1 = major.mm == 0 && next.mm != 0 ? next : major;
    const uint32_t predict1 = PredictBits(mm[3 * cabin + 1], base1);
    const uint32_t predict2 = PredictBits(mm[3 * cabin + 2], next);
    // | predict2:10 | predict1:10 | major:12 |
    PutU32(&bytes, major.code | (predict1 << 12) | (predict2 << 22));
  }
  SealCapsule(&bytes);
  return bytes;
}

}  // namespace aslam
