#include "drivers/sim/simulator.h"

#include "drivers/sim/lidar_models.h"
#include "drivers/sim/sim_test_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace aslam {
namespace {

VelocityCommand Command(const Simulator& sim, double linear_mps, double angular_radps) {
  return {sim.utime(), linear_mps, angular_radps};
}

// Expects the constructor to throw std::invalid_argument mentioning `name`.
void ExpectRejected(const SimulatorOptions& options, const std::string& name) {
  try {
    Simulator sim(RoomWithPillar(), {2.0, 2.0, 0.0}, options);
    ADD_FAILURE() << "no exception for " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(SimulatorTest, RejectsRatesThatDoNotDivideThePhysicsRate) {
  SimulatorOptions options;
  options.lidar.rate_hz = 30.0;
  ExpectRejected(options, "lidar.rate_hz");
  options = {};
  options.odometry_rate_hz = 40.0;  // 25000 us is not a multiple of 10000 us
  ExpectRejected(options, "odometry_rate_hz");
  options = {};
  options.truth_rate_hz = 200.0;  // faster than physics
  ExpectRejected(options, "truth_rate_hz");
  options = {};
  options.status_rate_hz = 0.0;
  ExpectRejected(options, "status_rate_hz");
  options = {};
  options.physics_rate_hz = 300.0;  // 3333.3 us
  ExpectRejected(options, "physics_rate_hz");
  options = {};
  options.robot.radius_m = -0.1;
  ExpectRejected(options, "robot.radius_m");
  options = {};
  options.robot.lidar_mount.yaw_rad = NAN;
  ExpectRejected(options, "robot.lidar_mount.yaw_rad");
  options = {};
  options.lidar.dropout_probability = 1.5;
  ExpectRejected(options, "lidar.dropout_probability");
  options = {};
  options.lidar.range_min_m = 20.0;
  ExpectRejected(options, "lidar.range_min_m");
  options = {};
  options.odometry_noise.alpha3 = -1.0;
  ExpectRejected(options, "odometry_noise.alpha3");
  options = {};
  options.physics_rate_hz = 200.0;
  options.lidar.rate_hz = 40.0;
  EXPECT_NO_THROW(Simulator(RoomWithPillar(), {2.0, 2.0, 0.0}, options));
}

TEST(SimulatorTest, RejectsAStartPoseInAWall) {
  EXPECT_THROW(Simulator(RoomWithPillar(), {0.1, 2.0, 0.0}, SimulatorOptions{}),
               std::invalid_argument);
  EXPECT_THROW(Simulator(RoomWithPillar(), {6.5, 5.5, 0.0}, SimulatorOptions{}),
               std::invalid_argument);
  EXPECT_THROW(Simulator(RoomWithPillar(), {-3.0, 2.0, 0.0}, SimulatorOptions{}),
               std::invalid_argument);
}

TEST(SimulatorTest, OutputsAreDueAtTheirPeriods) {
  Simulator sim(RoomWithPillar(), {2.0, 2.0, 0.0}, SimulatorOptions{});
  EXPECT_EQ(sim.utime(), 0);
  int odometry = 0, truth = 0, scans = 0, status = 0;
  for (int step = 1; step <= 300; ++step) {
    const SimStepOutput out = sim.Step();
    const int64_t now = step * 10000;
    ASSERT_EQ(sim.utime(), now);
    EXPECT_EQ(out.odometry.has_value(), now % 20000 == 0) << now;
    EXPECT_EQ(out.truth.has_value(), now % 20000 == 0) << now;
    EXPECT_EQ(out.scan.has_value(), now % 100000 == 0) << now;
    EXPECT_EQ(out.status.has_value(), now % 1000000 == 0) << now;
    if (out.odometry) {
      EXPECT_EQ(out.odometry->utime, now);
      EXPECT_EQ(out.odometry->seq, odometry);
      ++odometry;
    }
    if (out.truth) {
      EXPECT_EQ(out.truth->utime, now);
      ++truth;
    }
    if (out.scan) {
      EXPECT_EQ(out.scan->utime, now);
      EXPECT_EQ(out.scan->seq, scans);
      EXPECT_EQ(out.scan->range_m.size(), 720u);
      ++scans;
    }
    if (out.status) {
      EXPECT_EQ(out.status->utime, now);
      EXPECT_EQ(out.status->ticks, step);
      EXPECT_EQ(out.status->scans_published, scans);
      ++status;
    }
  }
  EXPECT_EQ(odometry, 150);
  EXPECT_EQ(truth, 150);
  EXPECT_EQ(scans, 30);
  EXPECT_EQ(status, 3);
  EXPECT_EQ(sim.ticks(), 300);
}

TEST(SimulatorTest, StandsStillWithoutACommandAndStopsWhenItGoesStale) {
  Simulator sim(RoomWithPillar(), {2.0, 2.0, 0.0}, SimulatorOptions{});
  for (int i = 0; i < 50; ++i) sim.Step();
  EXPECT_TRUE(sim.command_stale());
  EXPECT_EQ(sim.true_pose().x_m, 2.0);

  sim.SetCommand(Command(sim, 0.4, 0.0));
  sim.Step();
  EXPECT_FALSE(sim.command_stale());
  EXPECT_GT(sim.true_velocity().linear_mps, 0.0);
  // Valid for 0.5 s of its own time: at 0.5 s still driving, then the base brakes.
  for (int i = 1; i < 50; ++i) sim.Step();
  EXPECT_FALSE(sim.command_stale());
  EXPECT_NEAR(sim.true_velocity().linear_mps, 0.4, 1e-12);
  sim.Step();
  EXPECT_FALSE(sim.command_stale());  // judged at the step start: exactly 0.5 s old
  sim.Step();
  EXPECT_TRUE(sim.command_stale());
  EXPECT_LT(sim.true_velocity().linear_mps, 0.4);
  for (int i = 0; i < 50; ++i) sim.Step();
  EXPECT_EQ(sim.true_velocity().linear_mps, 0.0);
  const double stopped_x = sim.true_pose().x_m;
  for (int i = 0; i < 50; ++i) sim.Step();
  EXPECT_EQ(sim.true_pose().x_m, stopped_x);
  EXPECT_TRUE(sim.status().command_stale);
  EXPECT_EQ(sim.status().commands_received, 1);

  // A fresh command drives again; an old one is stale at once.
  sim.SetCommand(Command(sim, 0.2, 0.0));
  sim.Step();
  EXPECT_FALSE(sim.command_stale());
  sim.SetCommand({sim.utime() - 600000, 0.2, 0.0});
  sim.Step();
  EXPECT_TRUE(sim.command_stale());
}

TEST(SimulatorTest, CollisionsCountOncePerContact) {
  SimulatorOptions options;
  Simulator sim(RoomWithPillar(), {8.0, 2.0, 0.0}, options);  // wall face at x = 10
  auto drive = [&](double v, int steps) {
    for (int i = 0; i < steps; ++i) {
      sim.SetCommand(Command(sim, v, 0.0));
      sim.Step();
    }
  };
  drive(0.5, 600);  // reaches the wall after ~3.7 s and keeps pushing
  EXPECT_EQ(sim.collisions(), 1);
  EXPECT_TRUE(sim.in_collision());
  EXPECT_NEAR(10.0 - sim.true_pose().x_m, options.robot.radius_m, 0.01);
  EXPECT_EQ(sim.true_velocity().linear_mps, 0.0);
  EXPECT_TRUE(sim.status().in_collision);

  // Standing at the wall is still the same contact.
  drive(0.0, 100);
  EXPECT_TRUE(sim.in_collision());
  EXPECT_EQ(sim.collisions(), 1);

  drive(-0.3, 100);
  EXPECT_FALSE(sim.in_collision());
  EXPECT_EQ(sim.collisions(), 1);

  drive(0.5, 300);
  EXPECT_EQ(sim.collisions(), 2);
  EXPECT_TRUE(sim.in_collision());
  EXPECT_EQ(sim.status().collisions, 2);
}

TEST(SimulatorTest, NoiselessOdometryEqualsTruthInTheOdomFrame) {
  SimulatorOptions options;
  options.odometry_noise = {0.0, 0.0, 0.0, 0.0};
  const Pose2d start{2.0, 3.0, 0.7};
  Simulator sim(RoomWithPillar(), start, options);
  int checked = 0;
  for (int i = 0; i < 1000; ++i) {
    sim.SetCommand(Command(sim, 0.3, 0.6 * std::sin(0.01 * i)));
    const SimStepOutput out = sim.Step();
    if (!out.odometry) continue;
    const Pose2d expected = start.Between(sim.true_pose());
    EXPECT_NEAR(out.odometry->pose.x_m, expected.x_m, 1e-9);
    EXPECT_NEAR(out.odometry->pose.y_m, expected.y_m, 1e-9);
    EXPECT_NEAR(std::remainder(out.odometry->pose.yaw_rad - expected.yaw_rad, 2 * M_PI), 0.0, 1e-9);
    // Velocities implied by the (here exact) 20 ms delta: the chord over the period.
    EXPECT_NEAR(out.odometry->linear_velocity_mps, sim.true_velocity().linear_mps, 0.02);
    ++checked;
  }
  EXPECT_EQ(checked, 500);
  EXPECT_FALSE(sim.in_collision());
}

TEST(SimulatorTest, NoisyOdometryDrifts) {
  SimulatorOptions options;
  const Pose2d start{2.0, 3.0, 0.0};
  Simulator sim(RoomWithPillar(), start, options);
  for (int i = 0; i < 1500; ++i) {
    sim.SetCommand(Command(sim, 0.3, 0.5));
    sim.Step();
  }
  const Pose2d truth_in_odom = start.Between(sim.true_pose());
  const double drift =
      std::hypot(sim.odom_pose().x_m - truth_in_odom.x_m, sim.odom_pose().y_m - truth_in_odom.y_m);
  EXPECT_GT(drift, 1e-3);
  EXPECT_LT(drift, 1.0);
}

// Every scan range and odometry pose of a 2000-step run, as raw bytes.
std::string Record(uint64_t seed, const LidarOptions& lidar = {}) {
  SimulatorOptions options;
  options.seed = seed;
  options.lidar = lidar;
  Simulator sim(RoomWithPillar(), {3.0, 3.0, 0.2}, options);
  std::string bytes;
  auto append = [&bytes](const void* data, std::size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  for (int i = 0; i < 2000; ++i) {
    // Drives, turns, and hits walls along the way.
    sim.SetCommand(Command(sim, 0.5, (i / 300) % 2 == 0 ? 0.2 : -1.0));
    const SimStepOutput out = sim.Step();
    if (out.scan) append(out.scan->range_m.data(), out.scan->range_m.size() * sizeof(float));
    if (out.odometry) {
      append(&out.odometry->pose, sizeof(Pose2d));
      append(&out.odometry->linear_velocity_mps, sizeof(double));
      append(&out.odometry->angular_velocity_radps, sizeof(double));
    }
    if (out.truth) append(&out.truth->pose, sizeof(Pose2d));
  }
  return bytes;
}

std::string RecordOdometry(uint64_t seed, const LidarOptions& lidar) {
  SimulatorOptions options;
  options.seed = seed;
  options.lidar = lidar;
  Simulator sim(RoomWithPillar(), {3.0, 3.0, 0.2}, options);
  std::string bytes;
  for (int i = 0; i < 500; ++i) {
    sim.SetCommand(Command(sim, 0.4, 0.3));
    const SimStepOutput out = sim.Step();
    if (out.odometry) {
      bytes.append(reinterpret_cast<const char*>(&out.odometry->pose), sizeof(Pose2d));
    }
  }
  return bytes;
}

TEST(SimulatorTest, SameSeedGivesBitIdenticalOutputs) {
  const std::string a = Record(17), b = Record(17), c = Record(18);
  EXPECT_GT(a.size(), 20 * 720 * sizeof(float));
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
  EXPECT_EQ(a.size(), c.size());
}

TEST(SimulatorTest, LidarOptionsDoNotChangeTheOdometryNoise) {
  LidarOptions other;
  other.num_beams = 90;
  other.dropout_probability = 0.3;
  EXPECT_EQ(RecordOdometry(5, LidarOptions{}), RecordOdometry(5, other));
  EXPECT_NE(RecordOdometry(5, LidarOptions{}), RecordOdometry(6, LidarOptions{}));
}

TEST(SimulatorTest, TruthAndScanFollowTheTruePose) {
  SimulatorOptions options;
  options.lidar.noise_sigma_m = 0.0;
  options.lidar.noise_sigma_fraction = 0.0;
  options.lidar.dropout_probability = 0.0;
  Simulator sim(RoomWithPillar(), {2.0, 2.0, 0.0}, options);
  SimStepOutput out;
  for (int i = 0; i < 10; ++i) out = sim.Step();
  ASSERT_TRUE(out.scan && out.truth);
  EXPECT_EQ(out.truth->pose.x_m, 2.0);
  // Beam 360 looks along +x from (2, 2): the wall face at x = 10.
  EXPECT_NEAR(out.scan->range_m[360], 8.0, 1e-5);
  // Beam 540 looks along +y: 6 m to the top wall at y = 8.
  EXPECT_NEAR(out.scan->range_m[540], 6.0, 1e-5);
  EXPECT_EQ(sim.world().map().width_cells(), 202);
}

SimulatorOptions NoiselessLidar() {
  SimulatorOptions options;
  options.lidar.noise_sigma_m = 0.0;
  options.lidar.noise_sigma_fraction = 0.0;
  options.lidar.dropout_probability = 0.0;
  return options;
}

// The noiseless ranges a lidar at `sensor_in_world` reads, as a scan stores them.
std::vector<float> ExpectedRanges(const Simulator& sim, const Pose2d& sensor_in_world) {
  const LidarModel lidar(sim.options().lidar);
  std::vector<float> ranges;
  for (double range : lidar.ExactRanges(sim.world(), sensor_in_world)) {
    ranges.push_back(range <= lidar.options().range_max_m ? static_cast<float>(range) : 0.0f);
  }
  return ranges;
}

TEST(SimulatorTest, ScansAreCastFromTheLidarMount) {
  SimulatorOptions options = NoiselessLidar();
  options.robot.lidar_mount = {0.1, 0.0, M_PI / 2.0};  // 10 cm ahead, looking left
  Simulator sim(RoomWithPillar(), {2.0, 2.0, 0.0}, options);
  SimStepOutput out;
  for (int i = 0; i < 10; ++i) out = sim.Step();
  ASSERT_TRUE(out.scan);
  EXPECT_EQ(out.scan->sensor_pose.x_m, 0.1);
  EXPECT_EQ(out.scan->sensor_pose.y_m, 0.0);
  EXPECT_EQ(out.scan->sensor_pose.yaw_rad, M_PI / 2.0);
  // Beam 360 looks along the sensor's +x, world +y from (2.1, 2): the top wall at y = 8.
  EXPECT_NEAR(out.scan->range_m[360], 6.0, 1e-5);
  // Beam 540 looks along the sensor's +y, world -x: the left wall face at x = 0.
  EXPECT_NEAR(out.scan->range_m[540], 2.1, 1e-5);
  EXPECT_EQ(out.scan->range_m, ExpectedRanges(sim, sim.true_pose() * options.robot.lidar_mount));
}

// The default mount is the base centre: scans are cast from the true pose
// itself, bit for bit, while the robot turns through +-pi.
TEST(SimulatorTest, ZeroMountCastsFromTheBasePoseBitForBit) {
  Simulator sim(RoomWithPillar(), {3.0, 3.0, 0.2}, NoiselessLidar());
  int scans = 0;
  for (int i = 0; i < 1500; ++i) {
    sim.SetCommand(Command(sim, 0.1, 1.5));
    const SimStepOutput out = sim.Step();
    if (!out.scan) continue;
    ++scans;
    EXPECT_EQ(out.scan->sensor_pose.x_m, 0.0);
    EXPECT_EQ(out.scan->sensor_pose.yaw_rad, 0.0);
    ASSERT_EQ(out.scan->range_m, ExpectedRanges(sim, sim.true_pose())) << "scan " << scans;
  }
  EXPECT_EQ(scans, 150);
}

// A real model's sweep: each beam is cast from the true pose at its own time. The test
// interpolates the true poses it saw at every step and casts each beam itself.
TEST(SimulatorTest, SweptScansCastEachBeamFromThePoseAtItsTime) {
  SimulatorOptions options;
  options.lidar = LidarModelOptions("rplidar_a1");  // 5.5 Hz: sweeps start off the 10 ms grid
  options.lidar.noise_sigma_m = options.lidar.noise_sigma_fraction = 0.0;
  options.lidar.dropout_probability = 0.0;
  options.robot.lidar_mount = {0.05, 0.0, 0.0};
  Simulator sim(RoomWithPillar(), {3.0, 3.0, 0.2}, options);
  const LidarModel lidar(options.lidar);
  std::map<int64_t, Pose2d> truth{{0, sim.true_pose()}};
  std::vector<LidarScan> scans;
  for (int i = 0; i < 300; ++i) {  // 3 s turning at 1.5 rad/s while creeping forward
    sim.SetCommand(Command(sim, 0.1, 1.5));
    const SimStepOutput out = sim.Step();
    truth[sim.utime()] = sim.true_pose();
    if (out.scan) scans.push_back(*out.scan);
  }
  ASSERT_GE(scans.size(), 15u);  // 5.5 Hz for 3 s
  auto pose_at = [&](int64_t utime) {
    const auto after = truth.lower_bound(utime);
    if (after->first == utime) return after->second;
    const auto before = std::prev(after);
    const double f = static_cast<double>(utime - before->first) / (after->first - before->first);
    return Interpolate(before->second, after->second, f);
  };
  int smeared_beams = 0;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const LidarScan& scan = scans[k];
    EXPECT_EQ(scan.utime, std::llround(k * 1e6 / 5.5)) << "sweep " << k << " starts at k / rate";
    ASSERT_EQ(scan.beam_time_s.size(), 720u);
    // Clockwise head: the last beam (counter-clockwise order) is measured first.
    EXPECT_EQ(scan.beam_time_s[719], 0.0f);
    EXPECT_NEAR(scan.beam_time_s[0], 719.0 / 720.0 / 5.5, 1e-6);
    const std::vector<float> instantaneous =
        ExpectedRanges(sim, pose_at(scan.utime) * options.robot.lidar_mount);
    for (int beam = 0; beam < 720; ++beam) {
      const int64_t beam_utime = scan.utime + std::llround(scan.beam_time_s[beam] * 1e6);
      const double exact =
          lidar.ExactRange(sim.world(), pose_at(beam_utime) * options.robot.lidar_mount, beam);
      const float expected = exact <= options.lidar.range_max_m ? static_cast<float>(exact) : 0.0f;
      ASSERT_NEAR(scan.range_m[beam], expected, 1e-4) << "sweep " << k << " beam " << beam;
      if (std::abs(scan.range_m[beam] - instantaneous[beam]) > 0.05) ++smeared_beams;
    }
  }
  // Turning at 1.5 rad/s, a 0.18 s sweep is far from one instantaneous scan.
  EXPECT_GT(smeared_beams, 1000);
}

TEST(SimulatorTest, ASweptLidarWithAPartialFieldOfViewIdlesBetweenSweeps) {
  SimulatorOptions options = NoiselessLidar();
  options.lidar = LidarModelOptions("hokuyo_ust10");  // 40 Hz, 270° of the turn measured
  options.lidar.noise_sigma_m = options.lidar.noise_sigma_fraction = 0.0;
  options.lidar.dropout_probability = 0.0;
  Simulator sim(RoomWithPillar(), {3.0, 3.0, 0.0}, options);
  std::vector<LidarScan> scans;
  for (int i = 0; i < 100; ++i) {  // 1 s
    const SimStepOutput out = sim.Step();
    if (out.scan) scans.push_back(*out.scan);
  }
  ASSERT_EQ(scans.size(), 40u);
  for (const LidarScan& scan : scans) {
    ASSERT_EQ(scan.range_m.size(), 1081u);
    // Counter-clockwise head: beam order is time order, over 270/360 of the 25 ms period.
    EXPECT_EQ(scan.beam_time_s.front(), 0.0f);
    EXPECT_NEAR(scan.beam_time_s.back(), 1080 * 0.25 / 360.0 / 40.0, 1e-6);
    EXPECT_TRUE(std::is_sorted(scan.beam_time_s.begin(), scan.beam_time_s.end()));
  }
  EXPECT_EQ(scans[1].utime - scans[0].utime, 25000);
  // Standing still, the sweep reads what an instantaneous scan from the pose reads.
  EXPECT_EQ(scans.back().range_m, ExpectedRanges(sim, sim.true_pose()));
}

TEST(SimulatorTest, ASweptLidarMustNotOutrunThePhysicsStep) {
  SimulatorOptions options;
  options.lidar.swept = true;
  options.lidar.rate_hz = 5.5;  // fine: a swept lidar's rate need not divide physics
  EXPECT_NO_THROW(Simulator(RoomWithPillar(), {2.0, 2.0, 0.0}, options));
  options.lidar.rate_hz = 150.0;
  ExpectRejected(options, "lidar.rate_hz");
}

}  // namespace
}  // namespace aslam
