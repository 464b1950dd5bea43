#include "drivers/sim/lidar.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace aslam {
namespace {

// A walled room whose free interior is [0, width_m] x [0, height_m], walls on cell boundaries.
OccupancyGrid MakeRoom(double width_m, double height_m, double resolution_m = 0.05) {
  const int width = static_cast<int>(std::lround(width_m / resolution_m)) + 2;
  const int height = static_cast<int>(std::lround(height_m / resolution_m)) + 2;
  OccupancyGrid grid(width, height, resolution_m, {-resolution_m, -resolution_m},
                     OccupancyGrid::kFree);
  for (int col = 0; col < width; ++col) {
    grid.at({col, 0}) = grid.at({col, height - 1}) = OccupancyGrid::kOccupied;
  }
  for (int row = 0; row < height; ++row) {
    grid.at({0, row}) = grid.at({width - 1, row}) = OccupancyGrid::kOccupied;
  }
  return grid;
}

double DistanceToBox(double width_m, double height_m, Point2d p, double angle_rad) {
  const double dx = std::cos(angle_rad), dy = std::sin(angle_rad);
  double t = std::numeric_limits<double>::infinity();
  if (dx > 0) t = std::min(t, (width_m - p.x_m) / dx);
  if (dx < 0) t = std::min(t, -p.x_m / dx);
  if (dy > 0) t = std::min(t, (height_m - p.y_m) / dy);
  if (dy < 0) t = std::min(t, -p.y_m / dy);
  return t;
}

LidarOptions Noiseless() {
  LidarOptions options;
  options.noise_sigma_m = 0.0;
  options.noise_sigma_fraction = 0.0;
  options.dropout_probability = 0.0;
  return options;
}

TEST(LidarTest, ScanFieldsAndBeamLayout) {
  const SimWorld world(MakeRoom(6.0, 4.0));
  LidarOptions options;
  options.num_beams = 360;
  options.angle_min_rad = -2.0;
  options.fov_rad = 3.0;
  const LidarModel lidar(options);
  std::mt19937_64 rng(1);
  const LidarScan scan = lidar.Scan(world, {3.0, 2.0, 0.4}, 123456, 7, rng);
  EXPECT_EQ(scan.utime, 123456);
  EXPECT_EQ(scan.seq, 7);
  EXPECT_EQ(scan.range_m.size(), 360u);
  EXPECT_EQ(scan.angle_min_rad, -2.0);
  EXPECT_DOUBLE_EQ(scan.angle_increment_rad, 3.0 / 360);
  EXPECT_DOUBLE_EQ(lidar.BeamAngle(359), -2.0 + 359 * 3.0 / 360);
  EXPECT_TRUE(scan.beam_time_s.empty());
  EXPECT_EQ(scan.range_min_m, options.range_min_m);
  EXPECT_EQ(scan.range_max_m, options.range_max_m);
  EXPECT_EQ(scan.sensor_pose.x_m, 0.0);
  EXPECT_EQ(scan.sensor_pose.y_m, 0.0);
  EXPECT_EQ(scan.sensor_pose.yaw_rad, 0.0);
}

TEST(LidarTest, NoiselessRangesAreTheDistancesToTheWalls) {
  const double width = 7.0, height = 5.0;
  const SimWorld world(MakeRoom(width, height));
  const LidarModel lidar(Noiseless());
  for (const Pose2d& pose :
       {Pose2d{3.5, 2.5, 0.0}, Pose2d{0.4, 4.1, 2.3}, Pose2d{6.2, 0.9, -1.1}}) {
    const std::vector<double> exact = lidar.ExactRanges(world, pose);
    std::mt19937_64 rng(2);
    const LidarScan scan = lidar.Scan(world, pose, 0, 0, rng);
    ASSERT_EQ(exact.size(), 720u);
    for (int i = 0; i < 720; ++i) {
      const double expected =
          DistanceToBox(width, height, {pose.x_m, pose.y_m}, pose.yaw_rad + lidar.BeamAngle(i));
      EXPECT_NEAR(exact[i], expected, 1e-9) << "beam " << i;
      EXPECT_NEAR(scan.range_m[i], expected, 1e-6 * expected) << "beam " << i;
      EXPECT_TRUE(scan.IsValidReturn(i));
    }
  }
}

TEST(LidarTest, BeyondRangeMaxIsNoReturn) {
  const SimWorld world(MakeRoom(30.0, 4.0));
  LidarOptions options = Noiseless();
  options.range_max_m = 5.0;
  const LidarModel lidar(options);
  std::mt19937_64 rng(3);
  const Pose2d pose{2.0, 2.0, 0.0};
  const LidarScan scan = lidar.Scan(world, pose, 0, 0, rng);
  const std::vector<double> exact = lidar.ExactRanges(world, pose);
  int no_return = 0;
  for (int i = 0; i < lidar.num_beams(); ++i) {
    const double expected = DistanceToBox(30.0, 4.0, {2.0, 2.0}, lidar.BeamAngle(i));
    if (expected > 5.0 + 1e-9) {
      EXPECT_EQ(scan.range_m[i], 0.0f) << "beam " << i;
      EXPECT_EQ(exact[i], SimWorld::kNoHit);
      EXPECT_FALSE(scan.IsValidReturn(i));
      ++no_return;
    } else if (expected < 5.0 - 1e-9) {
      EXPECT_NEAR(scan.range_m[i], expected, 1e-5);
    }
  }
  EXPECT_GT(no_return, 50);  // the beams down the long room
}

TEST(LidarTest, ReadingsBelowRangeMinAreNoReturn) {
  const SimWorld world(MakeRoom(4.0, 4.0));
  LidarOptions options = Noiseless();
  options.range_min_m = 0.5;
  const LidarModel lidar(options);
  std::mt19937_64 rng(4);
  // 0.3 m from the left wall: beams that hit it closer than 0.5 m report nothing.
  const LidarScan scan = lidar.Scan(world, {0.3, 2.0, 0.0}, 0, 0, rng);
  int too_close = 0;
  for (int i = 0; i < lidar.num_beams(); ++i) {
    const double expected = DistanceToBox(4.0, 4.0, {0.3, 2.0}, lidar.BeamAngle(i));
    if (expected < 0.5 - 1e-9) {
      EXPECT_EQ(scan.range_m[i], 0.0f) << "beam " << i;
      ++too_close;
    } else if (expected > 0.5 + 1e-9) {
      EXPECT_NEAR(scan.range_m[i], expected, 1e-5) << "beam " << i;
    }
  }
  EXPECT_GT(too_close, 100);
}

TEST(LidarTest, NoiseHasTheConfiguredMeanAndSigma) {
  const SimWorld world(MakeRoom(10.0, 8.0));
  LidarOptions options = Noiseless();
  options.num_beams = 8;
  options.noise_sigma_m = 0.02;
  options.noise_sigma_fraction = 0.01;
  const LidarModel lidar(options);
  const Pose2d pose{2.0, 3.0, 0.3};
  const std::vector<double> exact = lidar.ExactRanges(world, pose);
  std::mt19937_64 rng(5);
  constexpr int kScans = 20000;
  std::vector<double> sum(8, 0.0), sum_sq(8, 0.0);
  for (int s = 0; s < kScans; ++s) {
    const LidarScan scan = lidar.Scan(world, pose, s, s, rng);
    for (int i = 0; i < 8; ++i) {
      const double error = scan.range_m[i] - exact[i];
      sum[i] += error;
      sum_sq[i] += error * error;
    }
  }
  for (int i = 0; i < 8; ++i) {
    const double sigma = 0.02 + 0.01 * exact[i];
    const double mean = sum[i] / kScans;
    const double std_dev = std::sqrt(sum_sq[i] / kScans - mean * mean);
    EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(kScans)) << "beam " << i;
    // The standard error of a sample sigma is sigma / sqrt(2N), 0.5% here.
    EXPECT_NEAR(std_dev, sigma, 0.025 * sigma) << "beam " << i;
  }
}

TEST(LidarTest, DropoutFractionMatchesTheProbability) {
  const SimWorld world(MakeRoom(10.0, 8.0));
  LidarOptions options = Noiseless();
  options.dropout_probability = 0.2;
  const LidarModel lidar(options);
  std::mt19937_64 rng(6);
  int beams = 0, dropped = 0;
  for (int s = 0; s < 100; ++s) {
    const LidarScan scan = lidar.Scan(world, {5.0, 4.0, 0.01 * s}, 0, s, rng);
    for (float range : scan.range_m) {
      ++beams;
      dropped += range == 0.0f;
    }
  }
  const double p = 0.2, n = beams;
  EXPECT_NEAR(dropped / n, p, 4.0 * std::sqrt(p * (1 - p) / n));
}

TEST(LidarTest, NoisyRangesAreClampedToRangeMax) {
  const SimWorld world(MakeRoom(10.0, 8.0));
  LidarOptions options = Noiseless();
  options.range_max_m = 3.0;
  options.noise_sigma_m = 0.2;
  const LidarModel lidar(options);
  std::mt19937_64 rng(7);
  int clamped = 0, returns = 0;
  // The right wall is 2.95 m away: about 40% of the noisy readings overshoot 3 m.
  for (int s = 0; s < 200; ++s) {
    const LidarScan scan = lidar.Scan(world, {7.05, 4.0, 0.0}, 0, s, rng);
    const int beam = lidar.num_beams() / 2;  // angle 0: straight at the wall
    ASSERT_LE(scan.range_m[beam], 3.0f);
    EXPECT_TRUE(scan.range_m[beam] == 0.0f || scan.IsValidReturn(beam));
    returns += scan.range_m[beam] > 0.0f;
    clamped += scan.range_m[beam] == 3.0f;
  }
  EXPECT_EQ(returns, 200);
  EXPECT_GT(clamped, 40);
  EXPECT_LT(clamped, 130);
}

TEST(LidarTest, SameSeedSameScanDifferentSeedDifferentScan) {
  const SimWorld world(MakeRoom(10.0, 8.0));
  const LidarModel lidar{LidarOptions{}};
  std::mt19937_64 a(99), b(99), c(100);
  const LidarScan scan_a = lidar.Scan(world, {3.0, 3.0, 1.0}, 0, 0, a);
  const LidarScan scan_b = lidar.Scan(world, {3.0, 3.0, 1.0}, 0, 0, b);
  const LidarScan scan_c = lidar.Scan(world, {3.0, 3.0, 1.0}, 0, 0, c);
  EXPECT_EQ(scan_a.range_m, scan_b.range_m);
  EXPECT_NE(scan_a.range_m, scan_c.range_m);
}

}  // namespace
}  // namespace aslam
