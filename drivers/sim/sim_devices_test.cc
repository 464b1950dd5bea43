#include "drivers/sim/sim_devices.h"

#include <gtest/gtest.h>
#include <cmath>
#include <string>
#include <vector>

#include "common/test_temp_dir.h"
#include "drivers/sim/sim_test_world.h"

namespace aslam {
namespace {

void ExpectPoseNear(const Pose2d& actual, const Pose2d& expected) {
  EXPECT_NEAR(actual.x_m, expected.x_m, 1e-9);
  EXPECT_NEAR(actual.y_m, expected.y_m, 1e-9);
  EXPECT_NEAR(std::remainder(actual.yaw_rad - expected.yaw_rad, 2.0 * M_PI), 0.0, 1e-9);
}

class SimDevicesTest : public ::testing::Test {
 protected:
  const std::string dir_ = TestTempDir();
};

// The emulated lidar measures beam by beam while the simulator steps at 50 Hz: a beam
// measured between two steps sees the pose between them, on the host clock SIM_TRUTH uses.
TEST_F(SimDevicesTest, TheLidarLooksFromThePoseAtTheInstantOfEachBeam) {
  Simulator simulator(RoomWithPillar(), {3.0, 4.0, 0.5}, SimulatorOptions());
  SimDevicesOptions options;
  options.dir = dir_;
  SimDevices devices(simulator, options);
  const Pose2d& mount = simulator.options().robot.lidar_mount;
  const Pose2d start_lidar = simulator.true_pose().Compose(mount);
  const int64_t host_minus_sim_us = 123456789;
  ExpectPoseNear(devices.LidarInWorldAt(host_minus_sim_us), start_lidar);  // before any step

  std::vector<int64_t> host_utimes;
  std::vector<Pose2d> lidar_poses;
  for (int step = 0; step < 25; ++step) {
    simulator.SetCommand({simulator.utime(), 0.3, 1.2});
    const SimStepOutput out = simulator.Step();
    host_utimes.push_back(simulator.utime() + host_minus_sim_us);
    lidar_poses.push_back(simulator.true_pose().Compose(mount));
    devices.AfterStep(out, host_utimes.back());
  }
  for (std::size_t k = 0; k + 1 < host_utimes.size(); ++k) {
    SCOPED_TRACE(k);
    ExpectPoseNear(devices.LidarInWorldAt(host_utimes[k]), lidar_poses[k]);
    const int64_t quarter_us = (host_utimes[k + 1] - host_utimes[k]) / 4;
    ExpectPoseNear(devices.LidarInWorldAt(host_utimes[k] + quarter_us),
                   Interpolate(lidar_poses[k], lidar_poses[k + 1], 0.25));
  }
  // Held at the ends: the first step's pose before it, the newest when the simulation lags.
  ExpectPoseNear(devices.LidarInWorldAt(host_utimes.front() - 5000), lidar_poses.front());
  ExpectPoseNear(devices.LidarInWorldAt(host_utimes.back() + 50000), lidar_poses.back());
  // The robot has sped up to turning and driving: poses a step apart differ, so the
  // interpolation was tested.
  const Pose2d last_step = lidar_poses[lidar_poses.size() - 2].Between(lidar_poses.back());
  EXPECT_GT(std::abs(last_step.yaw_rad), 1e-3);
  EXPECT_GT(std::abs(last_step.x_m), 1e-3);
}

}  // namespace
}  // namespace aslam
