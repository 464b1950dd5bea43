#pragma once

// A Yujin Kobuki base emulated on a pseudo-terminal, written from the Kobuki protocol
// specification alone (it shares no code with drivers/kobuki). It streams feedback
// packets every 20 ms (basic sensor data, inertial sensor data, and the other
// sub-payloads a real base sends, which a driver must skip), answers Request Extra
// (hardware version, firmware version, unique device id), and drives its wheels from
// Base Control (speed, radius) commands: the encoders, the gyro heading and the true
// pose follow. Faults can be injected: garbage, a packet with a bad checksum, a packet
// split across writes, bumper/cliff/wheel-drop events, encoder values near the 16-bit
// wrap, an unplug and a replug.
//
// The driver is given link_path(): a symlink the emulator re-points on replug, as udev
// re-points /dev/kobuki.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/io/pseudo_terminal.h"

namespace aslam {

struct KobukiEmulatorOptions {
  // Where the port's link is made ("" = in a temporary folder of the emulator's own).
  std::string link_path;
  // What Request Extra reports.
  uint8_t hardware_major = 1, hardware_minor = 0, hardware_patch = 4;
  uint8_t firmware_major = 1, firmware_minor = 2, firmware_patch = 0;
  uint32_t unique_id[3] = {0x12345678, 0x9abcdef0, 0x0badf00d};
  double feedback_period_s = 0.02;  // emulated seconds between feedback packets
  double time_scale = 1.0;          // emulated seconds per real second
  // The base's geometry, as the protocol document gives it.
  double wheel_radius_m = 0.035;
  double wheel_base_m = 0.230;
  double ticks_per_revolution = 2578.33;
  // The wheels reach a commanded speed at this rate (m/s² per wheel); 0 = at once.
  double wheel_accel_mps2 = 0.0;
  uint16_t initial_left_encoder = 0;
  uint16_t initial_right_encoder = 0;
  uint16_t initial_timestamp_ms = 0;
  double initial_gyro_deg = 0.0;  // the gyro's angle at power-on is arbitrary
  double battery_v = 16.0;
  uint8_t charger = 0;  // the protocol's charger state code
  // Also send docking IR, cliff sensor, current and general purpose input sub-payloads.
  bool send_other_sub_payloads = true;
  // Every byte arrives garbled, as at a wrong baud rate (never an AA 55 header); commands
  // sent to it are recorded but not understood.
  bool wrong_baud = false;
  // The wheels move as SetWheelSpeeds says (a simulator drives them), not as commanded.
  bool external_motion = false;
};

// A Base Control command as received.
struct KobukiBaseControl {
  int16_t speed_mm_s = 0;
  int16_t radius_mm = 0;
  double received_s = 0.0;  // emulated time of arrival
};

// Where the emulated base truly is (from its start) and how its wheels turn.
struct KobukiTruth {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;  // yaw wrapped to [-pi, pi), CCW positive
  double left_wheel_mps = 0.0, right_wheel_mps = 0.0;
  double time_s = 0.0;  // emulated time
};

class KobukiEmulator {
 public:
  explicit KobukiEmulator(KobukiEmulatorOptions options = {});
  ~KobukiEmulator();
  KobukiEmulator(const KobukiEmulator&) = delete;
  KobukiEmulator& operator=(const KobukiEmulator&) = delete;

  // The symlink to give the driver (absent while unplugged).
  const std::string& link_path() const { return link_.path(); }

  // Injections, taking effect in the emulator's thread from the next feedback packet.
  void SetBumper(uint8_t flags);     // 0x01 right, 0x02 central, 0x04 left
  void SetWheelDrop(uint8_t flags);  // 0x01 right, 0x02 left
  void SetCliff(uint8_t flags);      // 0x01 right, 0x02 central, 0x04 left
  void SetButtons(uint8_t flags);
  void SetBattery(double volts, uint8_t charger);
  void SetOvercurrent(uint8_t flags);               // 0x01 left, 0x02 right
  void SetEncoders(uint16_t left, uint16_t right);  // e.g. just below the wrap
  void InjectGarbage(const std::vector<uint8_t>& bytes);
  void CorruptNextFeedback();   // its checksum byte is wrong
  void SplitNextFeedback();     // sent in two writes a few milliseconds apart
  void SetSilent(bool silent);  // stops (or resumes) sending feedback, still plugged in
  void Unplug();                // both pty ends closed, the link removed; the base drives on
  void Replug();                // a new pseudo-terminal behind the link
  // external_motion: the wheels' speeds (m/s) from now on.
  void SetWheelSpeeds(double left_mps, double right_mps);

  // The wheel speeds the last Base Control asks for (m/s), as the base would drive them.
  void CommandedWheelSpeeds(double* left_mps, double* right_mps) const;
  KobukiTruth Truth() const;
  std::vector<KobukiBaseControl> ReceivedBaseControls() const;
  // Every byte the driver wrote, in order, across plugs.
  std::vector<uint8_t> ReceivedBytes() const;
  // Payloads of the well-formed packets the driver sent, and how many had a bad checksum.
  std::vector<std::vector<uint8_t>> ReceivedPayloads() const;
  int bad_packets_received() const;
  int64_t feedback_sent() const { return feedback_sent_; }
  int request_extra_received() const;

 private:
  void Run();
  // Writes to the master end (garbled first when wrong_baud); what does not fit is lost.
  void Send(std::vector<uint8_t> bytes);
  void HandleInput(const std::vector<uint8_t>& bytes);
  // Takes whole packets off the front of input_, resyncing past garbage.
  void ParseInput();
  void HandlePayload(const std::vector<uint8_t>& payload);
  void ApplyBaseControl(int16_t speed_mm_s, int16_t radius_mm);
  // Integrates the motion up to emulated time t_s in steps of at most one feedback period.
  void AdvanceTo(double t_s);
  void Step(double dt_s);
  std::vector<uint8_t> FeedbackPacket();
  double EmulatedNow() const;

  KobukiEmulatorOptions options_;
  DeviceLink link_;
  mutable std::mutex mutex_;
  std::unique_ptr<PseudoTerminal> pty_;
  double start_real_s_ = 0.0;
  double now_s_ = 0.0;  // emulated time of the thread's current iteration
  // Motion: integrated up to motion_time_s_ (emulated).
  double motion_time_s_ = 0.0;
  double target_left_mps_ = 0.0, target_right_mps_ = 0.0;  // commanded (or external)
  double command_left_mps_ = 0.0, command_right_mps_ = 0.0;
  KobukiTruth truth_;
  double left_ticks_frac_ = 0.0, right_ticks_frac_ = 0.0;
  uint16_t left_encoder_ = 0, right_encoder_ = 0;
  double yaw_total_rad_ = 0.0;     // unwrapped heading, for the gyro
  double yaw_rate_rad_s_ = 0.0;    // over the last step
  bool external_pending_ = false;  // SetWheelSpeeds values waiting for the thread
  double external_left_mps_ = 0.0, external_right_mps_ = 0.0;
  // Sensors and flags for the next feedback packets.
  uint8_t bumper_ = 0, wheel_drop_ = 0, cliff_ = 0, buttons_ = 0, overcurrent_ = 0;
  double battery_v_ = 0.0;
  uint8_t charger_ = 0;
  uint8_t gyro_frame_id_ = 0;
  // Controller gains (Set/Get Controller Gain), factory defaults per the spec.
  uint8_t gain_type_ = 0;
  uint32_t gain_p_ = 100000, gain_i_ = 100, gain_d_ = 2000;
  uint16_t pending_extra_ = 0;  // Request Extra flags not yet answered
  bool pending_controller_info_ = false;
  // Feedback schedule and faults.
  int64_t next_feedback_ = 1;  // index of the next packet; packet n is due at n periods
  bool silent_ = false;
  bool corrupt_next_ = false;
  bool split_next_ = false;
  std::vector<uint8_t> split_tail_;  // second half of a split packet, due at split_due_real_s_
  double split_due_real_s_ = 0.0;
  std::vector<uint8_t> pending_garbage_;
  uint32_t noise_state_ = 0x2545F491u;
  // What the driver sent.
  std::vector<uint8_t> input_;  // bytes not yet parsed
  double last_input_real_s_ = 0.0;
  std::vector<uint8_t> received_;
  std::vector<std::vector<uint8_t>> payloads_;
  std::vector<KobukiBaseControl> base_controls_;
  int bad_packets_ = 0;
  int request_extra_ = 0;
  std::atomic<int64_t> feedback_sent_{0};
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace aslam
