#pragma once

// What a base may drive at, given the newest CMD_VEL and its own hazard sensors: zero on a
// bumper, cliff or wheel drop until every one has cleared and a command newer than the
// clearing has arrived; zero once the newest command is older than the timeout (by its
// arrival: the sender's clock may be another machine's); speeds clamped to the robot's
// limits; acceleration limited, except that a hazard stops at once. No I/O here.

#include <cstdint>

#include "common/sensor_types.h"

namespace aslam {

struct BaseSafetyOptions {
  double command_timeout_s = 0.5;
  double max_linear_mps = 0.5;
  double max_angular_radps = 1.8;
  double max_linear_accel_mps2 = 1.0;
  double max_angular_accel_radps2 = 3.0;
};

struct Twist {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

class BaseSafety {
 public:
  explicit BaseSafety(BaseSafetyOptions options);

  // A CMD_VEL as it arrived (host clock). Non-finite commands are refused (returns false).
  bool OnCommand(const VelocityCommand& command, int64_t arrival_utime);
  // The hazard sensors as last read: any set bit stops the base.
  void OnHazards(uint8_t bumper, uint8_t cliff, uint8_t wheel_drop, int64_t utime);
  // What to send now; call at the base's command rate.
  Twist Next(int64_t now_utime);

  bool hazard_stop() const { return hazard_active_ || awaiting_command_after_hazard_; }
  bool command_timed_out() const { return timed_out_; }
  const Twist& last_output() const { return output_; }

 private:
  BaseSafetyOptions options_;
  VelocityCommand command_;
  int64_t command_arrival_utime_ = -1;  // -1: none yet
  bool hazard_active_ = false;
  bool awaiting_command_after_hazard_ = false;
  int64_t hazard_cleared_utime_ = 0;
  bool timed_out_ = true;
  Twist output_;
  int64_t last_output_utime_ = -1;
};

}  // namespace aslam
