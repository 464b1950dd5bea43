#pragma once

// The whole simulated robot in discrete simulated time: a diff-drive base in
// a grid world with a lidar and noisy wheel odometry. No LCM: the node
// (sim_node.h) publishes what Step() returns.

#include <cstdint>
#include <optional>
#include <random>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "drivers/sim/diff_drive.h"
#include "drivers/sim/lidar.h"
#include "drivers/sim/odometry_model.h"
#include "drivers/sim/sim_world.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

// Throws std::invalid_argument naming the offending option: non-positive or
// non-finite values, probabilities outside [0, 1], range_min_m >= range_max_m,
// and rates whose period is not a whole number of physics steps of whole
// microseconds.
void ValidateSimulatorOptions(const SimulatorOptions& options);

// The simulator's own state (SIM_STATUS).
struct SimStatus {
  int64_t utime = 0;
  int64_t ticks = 0;       // physics steps since start
  int64_t collisions = 0;  // contacts since start; one per contact until free again
  bool in_collision = false;
  bool command_stale = true;  // no command newer than the timeout: the base is stopped
  int64_t scans_published = 0;
  int64_t commands_received = 0;  // SetCommand calls
};

// What one Step() emits: each output is present when it is due at the new time.
struct SimStepOutput {
  std::optional<Odometry> odometry;  // base in "odom"
  std::optional<StampedPose> truth;  // base in "world", true velocities
  std::optional<LidarScan> scan;
  std::optional<SimStatus> status;
};

class Simulator {
 public:
  // A contact ends once the disc grown by this margin is free again.
  static constexpr double kContactReleaseMarginM = 0.01;

  // Throws std::invalid_argument on invalid options (ValidateSimulatorOptions)
  // or a start pose whose disc overlaps a solid cell.
  Simulator(const OccupancyGrid& world_map, const Pose2d& start_in_world,
            const SimulatorOptions& options);

  // Stores the latest command. It drives the base while
  // sim time - command.utime <= command_timeout_s, judged at the start of each
  // step; after that (and before the first command) the target velocity is 0
  // and command_stale is set.
  void SetCommand(const VelocityCommand& command);

  // Advances one physics step of 1/physics_rate_hz. Time starts at 0 and
  // nothing is emitted at t = 0: an output with period P is due at P, 2P, ...
  // (sim utime a multiple of P, in integer microseconds). Odometry applies the
  // noise model to the true motion since the previous odometry sample and
  // integrates it into the odom pose (identity at t = 0); its velocities are
  // those implied by that noisy delta over the odometry period (what wheel
  // encoders measure), truth carries the true velocities. Scans are cast from
  // the true pose ⊕ robot.lidar_mount and carry the mount as sensor_pose. A swept
  // lidar (lidar.swept) starts sweep k at k / rate_hz (any rate, not only whole physics
  // steps) and casts each beam from the true pose interpolated at the beam's own time;
  // its scan is emitted at the step that measures its last beam, stamped with the
  // sweep's start and carrying each beam's time after it.
  SimStepOutput Step();

  int64_t utime() const { return utime_; }
  int64_t ticks() const { return status_.ticks; }
  int64_t physics_period_us() const { return physics_period_us_; }
  const Pose2d& true_pose() const { return base_.pose(); }  // world frame
  const Twist2d& true_velocity() const { return base_.velocity(); }
  const Pose2d& odom_pose() const { return odom_pose_; }  // odom frame
  int64_t collisions() const { return status_.collisions; }
  bool in_collision() const { return status_.in_collision; }
  bool command_stale() const { return status_.command_stale; }
  SimStatus status() const;
  const SimWorld& world() const { return world_; }
  const SimulatorOptions& options() const { return options_; }

 private:
  SimulatorOptions options_;
  SimWorld world_;
  LidarModel lidar_;
  OdometryModel odometry_model_;
  DiffDriveBase base_;

  int64_t physics_period_us_ = 0;
  int64_t odometry_period_us_ = 0;
  int64_t truth_period_us_ = 0;
  int64_t lidar_period_us_ = 0;
  int64_t status_period_us_ = 0;
  int64_t command_timeout_us_ = 0;

  // Separate streams, seeded by std::seed_seq{seed, stream id}: lidar
  // settings never change the odometry noise and vice versa.
  std::mt19937_64 lidar_rng_;
  std::mt19937_64 odometry_rng_;

  int64_t utime_ = 0;
  std::optional<VelocityCommand> command_;
  SimStatus status_;
  Pose2d odom_pose_;
  Pose2d true_pose_at_last_odometry_;
  int64_t odometry_seq_ = 0;

  // The swept lidar's sweep in progress: exact ranges gathered beam by beam.
  struct Sweep {
    int64_t start_utime = 0;
    int next_k = 0;  // beams measured so far, in the head's order
    std::vector<double> exact_m;
  };
  std::optional<LidarScan> AdvanceSweep(const Pose2d& pose_before, const Pose2d& pose_after);
  int64_t SweepStartUtime(int64_t sweep) const;
  int64_t sweeps_started_ = 0;
  std::optional<Sweep> sweep_;
};

}  // namespace aslam
