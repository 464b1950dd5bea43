#include "drivers/emulators/kobuki_emulator.h"

#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

// Written from the Kobuki "Appendix: Protocol Specification" (kobuki_driver documentation) and
// its "Kobuki Parameters" appendix. Section names below are the spec's.
//
// Command timeout: the spec names none (Base Control has no duration or watchdog), so the
// emulated base keeps driving its last Base Control until told otherwise; a driver must send 0.

namespace aslam {
namespace {

constexpr uint8_t kHeader0 = 0xAA;
constexpr uint8_t kHeader1 = 0x55;

// Command Identifier table.
constexpr uint8_t kCmdBaseControl = 1;
constexpr uint8_t kCmdRequestExtra = 9;
constexpr uint8_t kCmdSetControllerGain = 13;
constexpr uint8_t kCmdGetControllerGain = 14;

// Feedback Identifier table.
constexpr uint8_t kFbBasicSensorData = 1;
constexpr uint8_t kFbDockingIr = 3;
constexpr uint8_t kFbInertialSensor = 4;
constexpr uint8_t kFbCliff = 5;
constexpr uint8_t kFbCurrent = 6;
constexpr uint8_t kFbHardwareVersion = 10;
constexpr uint8_t kFbFirmwareVersion = 11;
constexpr uint8_t kFbRawGyro = 13;
constexpr uint8_t kFbGeneralPurposeInput = 16;
constexpr uint8_t kFbUniqueDeviceId = 19;
constexpr uint8_t kFbControllerInfo = 21;

// Request Extra flags.
constexpr uint16_t kExtraHardwareVersion = 0x01;
constexpr uint16_t kExtraFirmwareVersion = 0x02;
constexpr uint16_t kExtraUniqueDeviceId = 0x08;

constexpr double kRawGyroDpsPerDigit = 0.00875;  // Raw Data Of 3D Gyro
constexpr double kPwmFullScaleMps = 0.7;         // wheel speed at PWM 100 (our model)
constexpr uint16_t kCliffFloorAdc = 2600;        // PSD reading over the floor (our model)
constexpr uint16_t kCliffDropAdc = 150;          // and over a cliff

double NowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void PutU8(std::vector<uint8_t>* bytes, unsigned value) {
  bytes->push_back(static_cast<uint8_t>(value & 0xFF));
}

void PutU16(std::vector<uint8_t>* bytes, unsigned value) {  // LSB first (Data Types)
  PutU8(bytes, value);
  PutU8(bytes, value >> 8);
}

void PutU32(std::vector<uint8_t>* bytes, uint32_t value) {
  PutU16(bytes, value & 0xFFFF);
  PutU16(bytes, value >> 16);
}

void PutS16(std::vector<uint8_t>* bytes, long value) {
  value = std::clamp<long>(value, -32768, 32767);
  PutU16(bytes, static_cast<uint16_t>(static_cast<int16_t>(value)));
}

uint16_t U16(const uint8_t* data) { return static_cast<uint16_t>(data[0] | (data[1] << 8)); }
uint32_t U32(const uint8_t* data) {
  return static_cast<uint32_t>(U16(data)) | (static_cast<uint32_t>(U16(data + 2)) << 16);
}

// Base Control conversion table: Speed is the outer wheel's speed; radius 0 = both wheels at
// Speed, radius 1 = pure rotation with Speed = w * b / 2 (right wheel +Speed, left -Speed, CCW
// for Speed > 0), |radius| > 1 = arc about a centre on the left (radius > 0) or right, where
// Speed = v (R + b/2) / R, resp. v (R - b/2) / R; radius -1 (not in the table) we read as the
// mirror of 1: left wheel +Speed, right -Speed (clockwise for Speed > 0).
void WheelSpeeds(int16_t speed_mm_s, int16_t radius_mm, double wheel_base_m, double* left_mps,
                 double* right_mps) {
  const double speed = speed_mm_s / 1000.0;
  if (radius_mm == 0) {
    *left_mps = *right_mps = speed;
    return;
  }
  const double radius = (radius_mm == 1 || radius_mm == -1) ? 0.0 : radius_mm / 1000.0;
  const double side = radius_mm > 0 ? 1.0 : -1.0;
  const double yaw_rate = speed / (radius + side * wheel_base_m / 2.0);
  *left_mps = yaw_rate * (radius - wheel_base_m / 2.0);
  *right_mps = yaw_rate * (radius + wheel_base_m / 2.0);
}

int8_t Pwm(double wheel_mps) {
  return static_cast<int8_t>(
      std::clamp<long>(std::lround(wheel_mps / kPwmFullScaleMps * 100.0), -100, 100));
}

double WrapDeg(double deg) {  // to [-180, 180)
  deg = std::fmod(deg + 180.0, 360.0);
  if (deg < 0.0) deg += 360.0;
  return deg - 180.0;
}

}  // namespace

KobukiEmulator::KobukiEmulator(KobukiEmulatorOptions options)
    : options_(std::move(options)), link_(options_.link_path, "kobuki") {
  if (!(options_.feedback_period_s > 0.0) || !(options_.time_scale > 0.0)) {
    throw std::invalid_argument("KobukiEmulator: feedback_period_s and time_scale must be > 0");
  }
  left_encoder_ = options_.initial_left_encoder;
  right_encoder_ = options_.initial_right_encoder;
  battery_v_ = options_.battery_v;
  charger_ = options_.charger;
  pty_ = std::make_unique<PseudoTerminal>();
  link_.PointAt(pty_->slave_path());
  start_real_s_ = NowS();
  thread_ = std::thread([this] { Run(); });
}

KobukiEmulator::~KobukiEmulator() {
  running_ = false;
  thread_.join();
}

void KobukiEmulator::SetBumper(uint8_t flags) {
  std::lock_guard<std::mutex> lock(mutex_);
  bumper_ = flags;
}

void KobukiEmulator::SetWheelDrop(uint8_t flags) {
  std::lock_guard<std::mutex> lock(mutex_);
  wheel_drop_ = flags;
}

void KobukiEmulator::SetCliff(uint8_t flags) {
  std::lock_guard<std::mutex> lock(mutex_);
  cliff_ = flags;
}

void KobukiEmulator::SetButtons(uint8_t flags) {
  std::lock_guard<std::mutex> lock(mutex_);
  buttons_ = flags;
}

void KobukiEmulator::SetBattery(double volts, uint8_t charger) {
  std::lock_guard<std::mutex> lock(mutex_);
  battery_v_ = volts;
  charger_ = charger;
}

void KobukiEmulator::SetOvercurrent(uint8_t flags) {
  std::lock_guard<std::mutex> lock(mutex_);
  overcurrent_ = flags;
}

void KobukiEmulator::SetEncoders(uint16_t left, uint16_t right) {
  std::lock_guard<std::mutex> lock(mutex_);
  left_encoder_ = left;
  right_encoder_ = right;
  left_ticks_frac_ = right_ticks_frac_ = 0.0;
}

void KobukiEmulator::InjectGarbage(const std::vector<uint8_t>& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_garbage_.insert(pending_garbage_.end(), bytes.begin(), bytes.end());
}

void KobukiEmulator::CorruptNextFeedback() {
  std::lock_guard<std::mutex> lock(mutex_);
  corrupt_next_ = true;
}

void KobukiEmulator::SplitNextFeedback() {
  std::lock_guard<std::mutex> lock(mutex_);
  split_next_ = true;
}

void KobukiEmulator::SetSilent(bool silent) {
  std::lock_guard<std::mutex> lock(mutex_);
  silent_ = silent;
}

void KobukiEmulator::Unplug() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (pty_) pty_->Close();
  pty_.reset();
  link_.Remove();
  input_.clear();
  split_tail_.clear();
}

void KobukiEmulator::Replug() {
  std::lock_guard<std::mutex> lock(mutex_);
  pty_ = std::make_unique<PseudoTerminal>();
  link_.PointAt(pty_->slave_path());
  input_.clear();
  split_tail_.clear();
}

void KobukiEmulator::SetWheelSpeeds(double left_mps, double right_mps) {
  std::lock_guard<std::mutex> lock(mutex_);
  external_pending_ = true;
  external_left_mps_ = left_mps;
  external_right_mps_ = right_mps;
}

void KobukiEmulator::CommandedWheelSpeeds(double* left_mps, double* right_mps) const {
  std::lock_guard<std::mutex> lock(mutex_);
  *left_mps = command_left_mps_;
  *right_mps = command_right_mps_;
}

KobukiTruth KobukiEmulator::Truth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return truth_;
}

std::vector<KobukiBaseControl> KobukiEmulator::ReceivedBaseControls() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return base_controls_;
}

std::vector<uint8_t> KobukiEmulator::ReceivedBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return received_;
}

std::vector<std::vector<uint8_t>> KobukiEmulator::ReceivedPayloads() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return payloads_;
}

int KobukiEmulator::bad_packets_received() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bad_packets_;
}

int KobukiEmulator::request_extra_received() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return request_extra_;
}

double KobukiEmulator::EmulatedNow() const {
  return (NowS() - start_real_s_) * options_.time_scale;
}

void KobukiEmulator::Send(std::vector<uint8_t> bytes) {
  if (!pty_ || bytes.empty()) return;
  if (options_.wrong_baud) {
    // Bits sampled at the wrong rate: noise, and never 0xAA, so never a packet header.
    for (uint8_t& b : bytes) {
      noise_state_ = noise_state_ * 1103515245u + 12345u;
      b = static_cast<uint8_t>(b ^ (noise_state_ >> 16));
      if (b == kHeader0) b = 0x2A;
    }
  }
  // A UART never blocks: what the receiver's buffer cannot take is lost.
  const ssize_t n = ::write(pty_->master_fd(), bytes.data(), bytes.size());
  (void)n;
}

void KobukiEmulator::Run() {
  const double period = options_.feedback_period_s;
  while (running_) {
    int fd = -1;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pty_) fd = pty_->master_fd();
    }
    if (fd >= 0) {
      pollfd p{fd, POLLIN, 0};
      ::poll(&p, 1, 1);  // wakes on the driver's bytes, else after 1 ms
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    std::lock_guard<std::mutex> lock(mutex_);
    const double now_real = NowS();
    if (!split_tail_.empty() && now_real >= split_due_real_s_) {
      Send(split_tail_);
      split_tail_.clear();
    }
    now_s_ = EmulatedNow();
    // Feedback packets due by now, each with the state at its own emulated time.
    for (int burst = 0; burst < 100 && next_feedback_ * period <= now_s_; ++burst) {
      AdvanceTo(next_feedback_ * period);
      ++next_feedback_;
      if (!pty_ || silent_) continue;
      std::vector<uint8_t> packet = FeedbackPacket();
      ++feedback_sent_;  // before its bytes leave: a reader that has them sees it counted
      if (!split_tail_.empty()) {
        Send(split_tail_);
        split_tail_.clear();
      }
      if (!pending_garbage_.empty()) {
        Send(pending_garbage_);
        pending_garbage_.clear();
      }
      if (split_next_) {
        split_next_ = false;
        const auto half = packet.begin() + static_cast<std::ptrdiff_t>(packet.size() / 2);
        Send(std::vector<uint8_t>(packet.begin(), half));
        split_tail_.assign(half, packet.end());
        split_due_real_s_ = now_real + 0.005;
      } else {
        Send(packet);
      }
    }
    now_s_ = std::min(now_s_, next_feedback_ * period);
    if (!pending_garbage_.empty() && split_tail_.empty() && pty_) {
      Send(pending_garbage_);
      pending_garbage_.clear();
    }
    if (external_pending_) {
      external_pending_ = false;
      AdvanceTo(now_s_);
      if (options_.external_motion) {
        target_left_mps_ = external_left_mps_;
        target_right_mps_ = external_right_mps_;
      }
    }
    if (pty_) {
      const std::vector<uint8_t> input = pty_->Read(0);
      if (!input.empty()) HandleInput(input);
    }
    ParseInput();
  }
}

void KobukiEmulator::HandleInput(const std::vector<uint8_t>& bytes) {
  received_.insert(received_.end(), bytes.begin(), bytes.end());
  if (options_.wrong_baud) return;  // at the wrong rate the base hears noise too
  input_.insert(input_.end(), bytes.begin(), bytes.end());
  last_input_real_s_ = NowS();
}

void KobukiEmulator::ParseInput() {
  // Structure of Bytestream: AA 55, length (>= 3), payload, XOR of length and payload.
  std::size_t at = 0;
  for (;;) {
    while (at + 1 < input_.size() && !(input_[at] == kHeader0 && input_[at + 1] == kHeader1)) {
      ++at;
    }
    if (at + 1 >= input_.size()) {
      if (at < input_.size() && input_[at] != kHeader0) at = input_.size();
      break;
    }
    if (at + 2 >= input_.size()) break;
    const std::size_t length = input_[at + 2];
    if (length < 3) {
      ++at;
      continue;
    }
    if (at + 4 + length > input_.size()) {
      // Incomplete: wait for the rest, unless nothing has come for a while (a false header).
      if (NowS() - last_input_real_s_ > 0.1) {
        ++at;
        continue;
      }
      break;
    }
    uint8_t checksum = 0;
    for (std::size_t i = at + 2; i < at + 4 + length; ++i) checksum ^= input_[i];
    if (checksum != 0) {
      ++bad_packets_;
      ++at;  // resync from the next byte
      continue;
    }
    std::vector<uint8_t> payload(input_.begin() + static_cast<std::ptrdiff_t>(at + 3),
                                 input_.begin() + static_cast<std::ptrdiff_t>(at + 3 + length));
    payloads_.push_back(payload);
    HandlePayload(payload);
    at += 4 + length;
  }
  input_.erase(input_.begin(), input_.begin() + static_cast<std::ptrdiff_t>(at));
}

void KobukiEmulator::HandlePayload(const std::vector<uint8_t>& payload) {
  std::size_t i = 0;
  while (i + 2 <= payload.size()) {
    const uint8_t id = payload[i];
    const std::size_t length = payload[i + 1];
    if (i + 2 + length > payload.size()) break;  // a sub-payload past the end: the rest is lost
    const uint8_t* data = payload.data() + i + 2;
    switch (id) {
      case kCmdBaseControl:
        if (length == 4) {
          ApplyBaseControl(static_cast<int16_t>(U16(data)), static_cast<int16_t>(U16(data + 2)));
        }
        break;
      case kCmdRequestExtra:
        if (length == 2) {
          pending_extra_ |= U16(data);
          ++request_extra_;
        }
        break;
      case kCmdSetControllerGain:  // type, P, I, D; the table's "identifier 1" is a typo for 13
        if (length == 13) {
          gain_type_ = data[0];
          gain_p_ = U32(data + 1);
          gain_i_ = U32(data + 5);
          gain_d_ = U32(data + 9);
        }
        break;
      case kCmdGetControllerGain: pending_controller_info_ = true; break;
      default: break;  // Sound (3), Sound Sequence (4), General Purpose Output (12), unknown ids
    }
    i += 2 + length;
  }
}

void KobukiEmulator::ApplyBaseControl(int16_t speed_mm_s, int16_t radius_mm) {
  AdvanceTo(now_s_);
  base_controls_.push_back({speed_mm_s, radius_mm, now_s_});
  WheelSpeeds(speed_mm_s, radius_mm, options_.wheel_base_m, &command_left_mps_,
              &command_right_mps_);
  if (!options_.external_motion) {
    target_left_mps_ = command_left_mps_;
    target_right_mps_ = command_right_mps_;
  }
}

void KobukiEmulator::AdvanceTo(double t_s) {
  while (motion_time_s_ < t_s - 1e-12) {
    const double dt = std::min(options_.feedback_period_s, t_s - motion_time_s_);
    Step(dt);
    motion_time_s_ += dt;
  }
  motion_time_s_ = std::max(motion_time_s_, t_s);
  truth_.time_s = motion_time_s_;
}

void KobukiEmulator::Step(double dt_s) {
  const double left0 = truth_.left_wheel_mps;
  const double right0 = truth_.right_wheel_mps;
  double left = target_left_mps_;
  double right = target_right_mps_;
  if (!options_.external_motion && options_.wheel_accel_mps2 > 0.0) {
    // Each wheel ramps towards its target, then holds it: its mean speed over the step.
    const double accel = options_.wheel_accel_mps2;
    auto ramp = [&](double from, double to, double* end) {
      const double reach_s = std::min(dt_s, std::abs(to - from) / accel);
      *end = from + std::copysign(accel * reach_s, to - from);
      return (0.5 * (from + *end) * reach_s + *end * (dt_s - reach_s)) / dt_s;
    };
    left = ramp(left0, target_left_mps_, &truth_.left_wheel_mps);
    right = ramp(right0, target_right_mps_, &truth_.right_wheel_mps);
  } else {
    truth_.left_wheel_mps = left;
    truth_.right_wheel_mps = right;
  }
  // Unicycle along an arc.
  const double v = 0.5 * (left + right);
  const double w = (right - left) / options_.wheel_base_m;
  const double yaw0 = truth_.yaw_rad;
  if (std::abs(w) < 1e-9) {
    truth_.x_m += v * dt_s * std::cos(yaw0);
    truth_.y_m += v * dt_s * std::sin(yaw0);
  } else {
    truth_.x_m += v / w * (std::sin(yaw0 + w * dt_s) - std::sin(yaw0));
    truth_.y_m -= v / w * (std::cos(yaw0 + w * dt_s) - std::cos(yaw0));
  }
  truth_.yaw_rad = std::remainder(yaw0 + w * dt_s, 2.0 * M_PI);
  if (truth_.yaw_rad >= M_PI) truth_.yaw_rad -= 2.0 * M_PI;
  yaw_total_rad_ += w * dt_s;
  yaw_rate_rad_s_ = w;
  // Encoders: ticks per metre of rim travel, the fraction kept for the next step.
  const double ticks_per_m = options_.ticks_per_revolution / (2.0 * M_PI * options_.wheel_radius_m);
  left_ticks_frac_ += left * dt_s * ticks_per_m;
  right_ticks_frac_ += right * dt_s * ticks_per_m;
  const double left_whole = std::floor(left_ticks_frac_);
  const double right_whole = std::floor(right_ticks_frac_);
  left_ticks_frac_ -= left_whole;
  right_ticks_frac_ -= right_whole;
  left_encoder_ = static_cast<uint16_t>(left_encoder_ + static_cast<int64_t>(left_whole));
  right_encoder_ = static_cast<uint16_t>(right_encoder_ + static_cast<int64_t>(right_whole));
}

std::vector<uint8_t> KobukiEmulator::FeedbackPacket() {
  std::vector<uint8_t> p;
  const double left = truth_.left_wheel_mps;
  const double right = truth_.right_wheel_mps;
  // Basic Sensor Data: 15 bytes.
  PutU8(&p, kFbBasicSensorData);
  PutU8(&p, 15);
  const long timestamp_ms = options_.initial_timestamp_ms + std::lround(motion_time_s_ * 1000.0);
  PutU16(&p, static_cast<unsigned>(timestamp_ms & 0xFFFF));  // circulates from 0 to 65535
  PutU8(&p, bumper_);
  PutU8(&p, wheel_drop_);
  PutU8(&p, cliff_);
  PutU16(&p, left_encoder_);
  PutU16(&p, right_encoder_);
  PutU8(&p, static_cast<uint8_t>(Pwm(left)));
  PutU8(&p, static_cast<uint8_t>(Pwm(right)));
  PutU8(&p, buttons_);
  PutU8(&p, charger_);
  PutU8(&p, static_cast<unsigned>(std::clamp<long>(std::lround(battery_v_ * 10.0), 0, 255)));
  PutU8(&p, overcurrent_);
  if (options_.send_other_sub_payloads) {  // Docking IR: right, central, left signals
    PutU8(&p, kFbDockingIr);
    PutU8(&p, 3);
    PutU8(&p, 0);
    PutU8(&p, 0);
    PutU8(&p, 0);
  }
  // Inertial Sensor Data: angle and angle rate (0.01 deg, 0.01 deg/s), three unused bytes.
  PutU8(&p, kFbInertialSensor);
  PutU8(&p, 7);
  const double angle_deg = WrapDeg(options_.initial_gyro_deg + yaw_total_rad_ * 180.0 / M_PI);
  PutS16(&p, std::lround(angle_deg * 100.0));
  const double rate_dps = yaw_rate_rad_s_ * 180.0 / M_PI;
  PutS16(&p, std::lround(rate_dps * 100.0));
  PutU8(&p, 0);
  PutU8(&p, 0);
  PutU8(&p, 0);
  if (options_.send_other_sub_payloads) {
    PutU8(&p, kFbCliff);  // PSD ADC: right, central, left
    PutU8(&p, 6);
    PutU16(&p, (cliff_ & 0x01) ? kCliffDropAdc : kCliffFloorAdc);
    PutU16(&p, (cliff_ & 0x02) ? kCliffDropAdc : kCliffFloorAdc);
    PutU16(&p, (cliff_ & 0x04) ? kCliffDropAdc : kCliffFloorAdc);
    PutU8(&p, kFbCurrent);  // length 2 as the table's header says: one byte (10 mA) per motor
    PutU8(&p, 2);
    PutU8(&p, static_cast<unsigned>(std::abs(Pwm(left))));
    PutU8(&p, static_cast<unsigned>(std::abs(Pwm(right))));
    // Raw 3D gyro: 2 or 3 readings a packet; robot z = sensor z, robot x = -sensor y.
    const int readings = (next_feedback_ % 2 == 0) ? 2 : 3;
    PutU8(&p, kFbRawGyro);
    PutU8(&p, static_cast<unsigned>(2 + 6 * readings));
    PutU8(&p, gyro_frame_id_);
    PutU8(&p, static_cast<unsigned>(3 * readings));
    for (int i = 0; i < readings; ++i) {
      PutS16(&p, 0);
      PutS16(&p, 0);
      PutS16(&p, std::lround(rate_dps / kRawGyroDpsPerDigit));
    }
    gyro_frame_id_ = static_cast<uint8_t>(gyro_frame_id_ + readings);
    PutU8(&p, kFbGeneralPurposeInput);  // digital in, 4 analog in, 3 unused: 16 bytes
    PutU8(&p, 16);
    for (int i = 0; i < 8; ++i) PutU16(&p, 0);
  }
  // On request: Hardware Version, Firmware Version (patch, minor, major, 0), UDID, gains.
  if (pending_extra_ & kExtraHardwareVersion) {
    PutU8(&p, kFbHardwareVersion);
    PutU8(&p, 4);
    PutU8(&p, options_.hardware_patch);
    PutU8(&p, options_.hardware_minor);
    PutU8(&p, options_.hardware_major);
    PutU8(&p, 0);
  }
  if (pending_extra_ & kExtraFirmwareVersion) {
    PutU8(&p, kFbFirmwareVersion);
    PutU8(&p, 4);
    PutU8(&p, options_.firmware_patch);
    PutU8(&p, options_.firmware_minor);
    PutU8(&p, options_.firmware_major);
    PutU8(&p, 0);
  }
  if (pending_extra_ & kExtraUniqueDeviceId) {
    PutU8(&p, kFbUniqueDeviceId);
    PutU8(&p, 12);
    for (uint32_t word : options_.unique_id) PutU32(&p, word);
  }
  pending_extra_ = 0;
  if (pending_controller_info_) {
    pending_controller_info_ = false;
    // Type, P, I, D: 13 bytes; the table's "identifier 1, length 21" swaps id and length.
    PutU8(&p, kFbControllerInfo);
    PutU8(&p, 13);
    PutU8(&p, gain_type_);
    PutU32(&p, gain_p_);
    PutU32(&p, gain_i_);
    PutU32(&p, gain_d_);
  }
  std::vector<uint8_t> packet;
  packet.reserve(p.size() + 4);
  packet.push_back(kHeader0);
  packet.push_back(kHeader1);
  packet.push_back(static_cast<uint8_t>(p.size()));
  uint8_t checksum = static_cast<uint8_t>(p.size());
  for (uint8_t b : p) {
    checksum ^= b;
    packet.push_back(b);
  }
  if (corrupt_next_) {
    corrupt_next_ = false;
    checksum ^= 0x5A;
  }
  packet.push_back(checksum);
  return packet;
}

}  // namespace aslam
