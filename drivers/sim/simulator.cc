#include "drivers/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace aslam {
namespace {

constexpr double kMicrosecondsPerSecond = 1e6;

[[noreturn]] void ThrowBadOption(const std::string& name, double value, const std::string& why) {
  std::ostringstream message;
  message << "SimulatorOptions: " << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

void RequirePositive(const std::string& name, double value) {
  if (!(std::isfinite(value) && value > 0.0)) ThrowBadOption(name, value, "must be finite and > 0");
}

void RequireFinite(const std::string& name, double value) {
  if (!std::isfinite(value)) ThrowBadOption(name, value, "must be finite");
}

void RequireNonNegative(const std::string& name, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    ThrowBadOption(name, value, "must be finite and >= 0");
  }
}

// A rate's period in whole microseconds; throws if it is not whole.
int64_t PeriodUs(const std::string& name, double rate_hz) {
  RequirePositive(name, rate_hz);
  const double period_us = kMicrosecondsPerSecond / rate_hz;
  const int64_t rounded = std::llround(period_us);
  if (rounded < 1 || std::abs(period_us - static_cast<double>(rounded)) > 1e-6) {
    ThrowBadOption(name, rate_hz, "period is not a whole number of microseconds");
  }
  return rounded;
}

// An output period that is a whole number of physics steps.
int64_t OutputPeriodUs(const std::string& name, double rate_hz, const SimulatorOptions& options) {
  const int64_t physics_period_us = PeriodUs("physics_rate_hz", options.physics_rate_hz);
  const int64_t period_us = PeriodUs(name, rate_hz);
  if (period_us % physics_period_us != 0) {
    std::ostringstream why;
    why << "must divide physics_rate_hz = " << options.physics_rate_hz << " (period " << period_us
        << " us is not a multiple of the " << physics_period_us << " us physics step)";
    ThrowBadOption(name, rate_hz, why.str());
  }
  return period_us;
}

// Two engines from one seed: a seed_seq mixes the stream id into the whole state.
std::mt19937_64 MakeStream(uint64_t seed, uint32_t stream) {
  std::seed_seq sequence{static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32), stream};
  return std::mt19937_64(sequence);
}

// Lets the constructor validate before any member is built from the options.
const SimulatorOptions& Validated(const SimulatorOptions& options) {
  ValidateSimulatorOptions(options);
  return options;
}

constexpr uint32_t kLidarStream = 1;
constexpr uint32_t kOdometryStream = 2;

}  // namespace

void ValidateSimulatorOptions(const SimulatorOptions& options) {
  OutputPeriodUs("odometry_rate_hz", options.odometry_rate_hz, options);
  OutputPeriodUs("truth_rate_hz", options.truth_rate_hz, options);
  OutputPeriodUs("status_rate_hz", options.status_rate_hz, options);
  if (options.lidar.swept) {
    // Sweeps start at k / rate_hz, off the physics grid if need be; one ends per step at most.
    RequirePositive("lidar.rate_hz", options.lidar.rate_hz);
    if (options.lidar.rate_hz > options.physics_rate_hz) {
      ThrowBadOption("lidar.rate_hz", options.lidar.rate_hz,
                     "a swept lidar must not turn faster than physics_rate_hz");
    }
  } else {
    OutputPeriodUs("lidar.rate_hz", options.lidar.rate_hz, options);
  }
  RequirePositive("command_timeout_s", options.command_timeout_s);

  const LidarOptions& lidar = options.lidar;
  if (lidar.num_beams < 1) ThrowBadOption("lidar.num_beams", lidar.num_beams, "must be >= 1");
  if (!std::isfinite(lidar.angle_min_rad)) {
    ThrowBadOption("lidar.angle_min_rad", lidar.angle_min_rad, "must be finite");
  }
  RequirePositive("lidar.fov_rad", lidar.fov_rad);
  if (lidar.fov_rad > 2.0 * M_PI + 1e-9) {
    ThrowBadOption("lidar.fov_rad", lidar.fov_rad, "must be <= 2 pi");
  }
  RequireNonNegative("lidar.range_min_m", lidar.range_min_m);
  RequirePositive("lidar.range_max_m", lidar.range_max_m);
  if (lidar.range_min_m >= lidar.range_max_m) {
    ThrowBadOption("lidar.range_min_m", lidar.range_min_m, "must be < lidar.range_max_m");
  }
  RequireNonNegative("lidar.noise_sigma_m", lidar.noise_sigma_m);
  RequireNonNegative("lidar.noise_sigma_fraction", lidar.noise_sigma_fraction);
  if (!(lidar.dropout_probability >= 0.0 && lidar.dropout_probability <= 1.0)) {
    ThrowBadOption("lidar.dropout_probability", lidar.dropout_probability, "must be in [0, 1]");
  }

  const RobotOptions& robot = options.robot;
  RequirePositive("robot.radius_m", robot.radius_m);
  RequirePositive("robot.max_linear_mps", robot.max_linear_mps);
  RequirePositive("robot.max_angular_radps", robot.max_angular_radps);
  RequirePositive("robot.max_linear_accel_mps2", robot.max_linear_accel_mps2);
  RequirePositive("robot.max_angular_accel_radps2", robot.max_angular_accel_radps2);
  RequireFinite("robot.lidar_mount.x_m", robot.lidar_mount.x_m);
  RequireFinite("robot.lidar_mount.y_m", robot.lidar_mount.y_m);
  RequireFinite("robot.lidar_mount.yaw_rad", robot.lidar_mount.yaw_rad);

  const OdometryNoiseOptions& noise = options.odometry_noise;
  RequireNonNegative("odometry_noise.alpha1", noise.alpha1);
  RequireNonNegative("odometry_noise.alpha2", noise.alpha2);
  RequireNonNegative("odometry_noise.alpha3", noise.alpha3);
  RequireNonNegative("odometry_noise.alpha4", noise.alpha4);
}

Simulator::Simulator(const OccupancyGrid& world_map, const Pose2d& start_in_world,
                     const SimulatorOptions& options)
    : options_(Validated(options)),
      world_(world_map),
      lidar_(options.lidar),
      odometry_model_(options.odometry_noise),
      base_(options.robot, start_in_world),
      physics_period_us_(PeriodUs("physics_rate_hz", options.physics_rate_hz)),
      odometry_period_us_(PeriodUs("odometry_rate_hz", options.odometry_rate_hz)),
      truth_period_us_(PeriodUs("truth_rate_hz", options.truth_rate_hz)),
      lidar_period_us_(options.lidar.swept ? 0 : PeriodUs("lidar.rate_hz", options.lidar.rate_hz)),
      status_period_us_(PeriodUs("status_rate_hz", options.status_rate_hz)),
      command_timeout_us_(std::llround(options.command_timeout_s * kMicrosecondsPerSecond)),
      lidar_rng_(MakeStream(options.seed, kLidarStream)),
      odometry_rng_(MakeStream(options.seed, kOdometryStream)),
      true_pose_at_last_odometry_(start_in_world) {
  if (world_.CircleCollides({start_in_world.x_m, start_in_world.y_m}, options.robot.radius_m)) {
    std::ostringstream message;
    message << "Simulator: start pose " << start_in_world
            << " with robot.radius_m = " << options.robot.radius_m
            << " overlaps a wall, unknown space or the map edge";
    throw std::invalid_argument(message.str());
  }
}

void Simulator::SetCommand(const VelocityCommand& command) {
  command_ = command;
  ++status_.commands_received;
}

SimStatus Simulator::status() const {
  SimStatus status = status_;
  status.utime = utime_;
  return status;
}

SimStepOutput Simulator::Step() {
  // The command in force during [utime, utime + step) is judged at the step's start.
  Twist2d target;
  status_.command_stale = !command_ || utime_ - command_->utime > command_timeout_us_;
  if (!status_.command_stale) target = {command_->linear_mps, command_->angular_radps};

  const double dt_s = physics_period_us_ / kMicrosecondsPerSecond;
  const Pose2d pose_before = base_.pose();
  const DiffDriveStepResult moved = base_.Step(target, dt_s, world_);
  utime_ += physics_period_us_;
  ++status_.ticks;

  const Pose2d& pose = base_.pose();
  if (moved.collided) {
    if (!status_.in_collision) ++status_.collisions;
    status_.in_collision = true;
  } else if (status_.in_collision &&
             !world_.CircleCollides({pose.x_m, pose.y_m},
                                    options_.robot.radius_m + kContactReleaseMarginM)) {
    status_.in_collision = false;
  }

  SimStepOutput out;
  if (utime_ % odometry_period_us_ == 0) {
    const Pose2d true_delta = true_pose_at_last_odometry_.Between(pose);
    const Pose2d noisy_delta = odometry_model_.NoisyDelta(true_delta, odometry_rng_);
    odom_pose_ = odom_pose_ * noisy_delta;
    true_pose_at_last_odometry_ = pose;
    const double period_s = odometry_period_us_ / kMicrosecondsPerSecond;
    Odometry odometry;
    odometry.utime = utime_;
    odometry.seq = odometry_seq_++;
    odometry.pose = odom_pose_;
    odometry.linear_velocity_mps = OdometryModel::Decompose(noisy_delta).trans_m / period_s;
    odometry.angular_velocity_radps = noisy_delta.yaw_rad / period_s;
    out.odometry = odometry;
  }
  if (utime_ % truth_period_us_ == 0) {
    out.truth =
        StampedPose{utime_, pose, base_.velocity().linear_mps, base_.velocity().angular_radps};
  }
  if (options_.lidar.swept) {
    out.scan = AdvanceSweep(pose_before, pose);
  } else if (utime_ % lidar_period_us_ == 0) {
    // Cast from base ⊕ mount: bit for bit the base pose when the mount is zero (pose2d_test).
    const Pose2d& mount = options_.robot.lidar_mount;
    out.scan = lidar_.Scan(world_, pose * mount, utime_, status_.scans_published, lidar_rng_);
    out.scan->sensor_pose = mount;
    ++status_.scans_published;
  }
  if (utime_ % status_period_us_ == 0) out.status = status();
  return out;
}

int64_t Simulator::SweepStartUtime(int64_t sweep) const {
  return std::llround(sweep * kMicrosecondsPerSecond / options_.lidar.rate_hz);
}

std::optional<LidarScan> Simulator::AdvanceSweep(const Pose2d& pose_before,
                                                 const Pose2d& pose_after) {
  const int64_t step_start_utime = utime_ - physics_period_us_;
  const int num_beams = lidar_.num_beams();
  const Pose2d& mount = options_.robot.lidar_mount;
  std::optional<LidarScan> finished;
  // The next sweep may start within this step, after the previous one ends in it.
  while (sweep_ || SweepStartUtime(sweeps_started_) <= utime_) {
    if (!sweep_) {
      sweep_ = Sweep{SweepStartUtime(sweeps_started_++), 0, std::vector<double>(num_beams)};
    }
    for (; sweep_->next_k < num_beams; ++sweep_->next_k) {
      const int64_t beam_utime =
          sweep_->start_utime + std::llround(lidar_.SweepTimeOfS(sweep_->next_k) * 1e6);
      if (beam_utime > utime_) return finished;
      // The base moves at constant velocities within a step: interpolate along it.
      const double f = std::clamp(
          static_cast<double>(beam_utime - step_start_utime) / physics_period_us_, 0.0, 1.0);
      const Pose2d pose = Interpolate(pose_before, pose_after, f);
      const int beam = lidar_.BeamMeasuredAt(sweep_->next_k);
      sweep_->exact_m[beam] = lidar_.ExactRange(world_, pose * mount, beam);
    }
    finished = lidar_.ScanFromExactRanges(sweep_->exact_m, sweep_->start_utime,
                                          status_.scans_published, lidar_rng_);
    finished->sensor_pose = mount;
    finished->beam_time_s.resize(num_beams);
    for (int k = 0; k < num_beams; ++k) {
      const int64_t offset_us = std::llround(lidar_.SweepTimeOfS(k) * 1e6);
      finished->beam_time_s[lidar_.BeamMeasuredAt(k)] = static_cast<float>(offset_us * 1e-6);
    }
    ++status_.scans_published;
    sweep_.reset();
  }
  return finished;
}

}  // namespace aslam
