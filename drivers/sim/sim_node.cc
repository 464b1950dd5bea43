#include "drivers/sim/sim_node.h"

#include <chrono>
#include <cmath>
#include <thread>

#include "common/channels.h"
#include "common/types_lcm.h"
#include "drivers/sim/sim_devices.h"
#include "drivers/sim/sim_lcm.h"

namespace aslam {

SimNode::SimNode(lcm::LCM& lcm, Simulator& simulator, SimNodeOptions options)
    : lcm_(lcm), simulator_(simulator), options_(std::move(options)), subscriptions_(lcm) {
  subscriptions_.Add<velocity_command_t>(
      channels::kCmdVel, [this](const velocity_command_t& msg) { return OnCommand(msg); });
}

bool SimNode::OnCommand(const velocity_command_t& msg) {
  const auto command = FromLcm(msg);
  if (!command) return false;
  ++commands_received_;
  if (!options_.drive && !options_.devices) simulator_.SetCommand(*command);
  return true;
}

bool SimNode::drive_finished() const {
  return options_.drive && !options_.drive->CommandAt(simulator_.utime()).has_value();
}

void SimNode::Tick() {
  if (options_.drive) {
    if (const auto command = options_.drive->CommandAt(simulator_.utime())) {
      simulator_.SetCommand(*command);
    }
  }
  if (options_.devices) simulator_.SetCommand(options_.devices->Command(simulator_.utime()));
  const SimStepOutput out = simulator_.Step();
  if (options_.devices) {
    options_.devices->AfterStep(out, simulator_.utime() + host_clock_offset_us_);
  } else {
    if (out.odometry) {
      const odometry_t msg = ToLcm(*out.odometry);
      lcm_.publish(channels::kOdometry, &msg);
    }
    if (out.scan) {
      const lidar_scan_t msg = ToLcm(*out.scan);
      lcm_.publish(channels::kLidarScan, &msg);
    }
  }
  if (out.truth) {
    StampedPose truth = *out.truth;
    truth.utime += host_clock_offset_us_;
    const pose_t msg = ToLcm(truth, "world");
    lcm_.publish(channels::kSimTruth, &msg);
  }
  if (out.status) {
    const sim_status_t msg =
        ToLcm(*out.status, {options_.world_label, simulator_.options().seed, real_time_factor_,
                            commands_received_, subscriptions_.total_dropped()});
    lcm_.publish(channels::kSimStatus, &msg);
  }
}

double RunRealTime(lcm::LCM& lcm, SimNode& node, const RealTimeOptions& options,
                   const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const int64_t start_utime = node.utime();
  const int64_t end_utime =
      options.duration_s > 0 ? start_utime + std::llround(options.duration_s * 1e6) : INT64_MAX;
  const Clock::time_point wall_start = Clock::now();
  Clock::time_point window_wall = wall_start;
  int64_t window_utime = start_utime;
  int64_t next_second_utime = start_utime + 1'000'000;

  while (!stop.load() && node.utime() < end_utime && !node.drive_finished()) {
    node.Tick();
    const int64_t sim_elapsed_us = node.utime() - start_utime;
    if (options.real_time_factor > 0) {
      // Pace against the absolute schedule so waiting errors never accumulate.
      const auto due = wall_start + std::chrono::microseconds(static_cast<int64_t>(
                                        sim_elapsed_us / options.real_time_factor));
      for (auto now = Clock::now(); now < due && !stop.load(); now = Clock::now()) {
        const auto wait_ms =
            std::chrono::duration_cast<std::chrono::milliseconds>(due - now).count();
        if (wait_ms == 0) {
          std::this_thread::sleep_until(due);  // under 1 ms: LCM's timeout cannot express it
        } else if (lcm.handleTimeout(static_cast<int>(wait_ms)) < 0) {
          break;
        }
      }
    }
    while (lcm.handleTimeout(0) > 0) {
    }
    if (node.utime() >= next_second_utime) {
      next_second_utime += 1'000'000;
      const Clock::time_point now = Clock::now();
      const double wall_s = std::chrono::duration<double>(now - window_wall).count();
      if (wall_s > 0) node.set_real_time_factor((node.utime() - window_utime) * 1e-6 / wall_s);
      window_wall = now;
      window_utime = node.utime();
      if (options.every_second) options.every_second(node);
    }
  }
  return (node.utime() - start_utime) * 1e-6;
}

}  // namespace aslam
