#pragma once

// The simulator on LCM: subscribes CMD_VEL, publishes LIDAR_SCAN, ODOMETRY,
// SIM_TRUTH and SIM_STATUS. The same node runs in both hostings (docs/architecture.md §4):
// ticked by InProcessHost on memq://, or paced against the wall clock by
// RunRealTime in the aslam-sim process.

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "aslam/velocity_command_t.hpp"
#include "common/lcm_util.h"
#include "drivers/sim/scripted_drive.h"
#include "drivers/sim/simulator.h"

namespace aslam {

class SimDevices;

struct SimNodeOptions {
  std::string world_label;             // reported in SIM_STATUS
  std::optional<ScriptedDrive> drive;  // when set, followed instead of CMD_VEL
  // When set, the base and lidar are emulated devices (sim_devices.h): commands come from
  // the base's driver, and ODOMETRY and LIDAR_SCAN from the drivers, not from this node.
  SimDevices* devices = nullptr;
};

class SimNode {
 public:
  SimNode(lcm::LCM& lcm, Simulator& simulator, SimNodeOptions options);

  // Advances one physics step and publishes what is due: ODOMETRY before
  // LIDAR_SCAN of the same time, then SIM_TRUTH and SIM_STATUS.
  void Tick();

  int64_t utime() const { return simulator_.utime(); }
  // True once a scripted drive has run out (never without a drive).
  bool drive_finished() const;
  const Simulator& simulator() const { return simulator_; }
  const Subscriptions& subscriptions() const { return subscriptions_; }
  // Process mode reports its measured speed in SIM_STATUS.
  void set_real_time_factor(double factor) { real_time_factor_ = factor; }
  // SIM_TRUTH and the emulated devices on the host's monotonic clock (simulated time +
  // offset), so truth lines up with what device drivers stamp; SIM_STATUS keeps simulated time.
  void set_host_clock_offset_us(int64_t offset_us) { host_clock_offset_us_ = offset_us; }

 private:
  bool OnCommand(const velocity_command_t& msg);

  lcm::LCM& lcm_;
  Simulator& simulator_;
  SimNodeOptions options_;
  Subscriptions subscriptions_;
  int64_t commands_received_ = 0;
  double real_time_factor_ = 0.0;
  int64_t host_clock_offset_us_ = 0;
};

struct RealTimeOptions {
  double real_time_factor = 1.0;  // simulated seconds per wall second; 0 = as fast as possible
  double duration_s = 0.0;        // simulated seconds to run; 0 = until stopped or the drive ends
  // Called once per simulated second, e.g. to print progress.
  std::function<void(const SimNode&)> every_second;
};

// Process mode: ticks `node` paced to the wall clock, handling incoming
// messages between ticks, until the duration is reached, a scripted drive
// ends, or `stop` becomes true. Returns the simulated seconds run.
double RunRealTime(lcm::LCM& lcm, SimNode& node, const RealTimeOptions& options,
                   const std::atomic<bool>& stop);

}  // namespace aslam
