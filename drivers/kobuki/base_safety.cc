#include "drivers/kobuki/base_safety.h"

#include <algorithm>
#include <cmath>

namespace aslam {
namespace {

double Toward(double from, double to, double max_step) {
  return from + std::clamp(to - from, -max_step, max_step);
}

}  // namespace

BaseSafety::BaseSafety(BaseSafetyOptions options) : options_(options) {}

bool BaseSafety::OnCommand(const VelocityCommand& command, int64_t arrival_utime) {
  if (!std::isfinite(command.linear_mps) || !std::isfinite(command.angular_radps)) return false;
  command_ = command;
  command_arrival_utime_ = arrival_utime;
  if (awaiting_command_after_hazard_ && !hazard_active_ && arrival_utime > hazard_cleared_utime_) {
    awaiting_command_after_hazard_ = false;
  }
  return true;
}

void BaseSafety::OnHazards(uint8_t bumper, uint8_t cliff, uint8_t wheel_drop, int64_t utime) {
  const bool active = (bumper | cliff | wheel_drop) != 0;
  if (active) {
    hazard_active_ = true;
    awaiting_command_after_hazard_ = true;
  } else if (hazard_active_) {
    hazard_active_ = false;
    hazard_cleared_utime_ = utime;
  }
}

Twist BaseSafety::Next(int64_t now_utime) {
  const double dt_s =
      last_output_utime_ < 0 ? 0.0 : std::max<int64_t>(now_utime - last_output_utime_, 0) * 1e-6;
  last_output_utime_ = now_utime;
  timed_out_ = command_arrival_utime_ < 0 ||
               now_utime - command_arrival_utime_ > options_.command_timeout_s * 1e6;
  if (hazard_stop()) {
    output_ = Twist{};
    return output_;
  }
  Twist target;
  if (!timed_out_) {
    target.linear_mps =
        std::clamp(command_.linear_mps, -options_.max_linear_mps, options_.max_linear_mps);
    target.angular_radps =
        std::clamp(command_.angular_radps, -options_.max_angular_radps, options_.max_angular_radps);
  }
  output_.linear_mps =
      Toward(output_.linear_mps, target.linear_mps, options_.max_linear_accel_mps2 * dt_s);
  output_.angular_radps =
      Toward(output_.angular_radps, target.angular_radps, options_.max_angular_accel_radps2 * dt_s);
  return output_;
}

}  // namespace aslam
