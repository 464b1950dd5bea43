#include "slam/scan_deskew.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

constexpr double kRoomHalfSizeM = 5.0;  // walls at x, y = ±5

// Distance from `origin` along `angle` to the square room's walls.
double RangeToRoomWalls(const Point2d& origin, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double t = 1e9;
  if (dx > 1e-12) t = std::min(t, (kRoomHalfSizeM - origin.x_m) / dx);
  if (dx < -1e-12) t = std::min(t, (-kRoomHalfSizeM - origin.x_m) / dx);
  if (dy > 1e-12) t = std::min(t, (kRoomHalfSizeM - origin.y_m) / dy);
  if (dy < -1e-12) t = std::min(t, (-kRoomHalfSizeM - origin.y_m) / dy);
  return t;
}

// The robot drives forward at 0.4 m/s while turning at 1.8 rad/s (the base's limit).
Pose2d BaseInWorld(double t_s) { return {-1.0 + 0.4 * t_s, 0.5, 0.3 + 1.8 * t_s}; }

LidarScan EmptyScan(int num_beams, double fov_rad, const Pose2d& mount) {
  LidarScan scan;
  scan.utime = 1000000;
  scan.sensor_pose = mount;
  scan.angle_min_rad = fov_rad >= 2 * M_PI ? -M_PI : -fov_rad / 2;
  scan.angle_increment_rad = fov_rad / num_beams;
  scan.range_min_m = 0.15;
  scan.range_max_m = 12.0;
  scan.range_m.assign(num_beams, 0.0f);
  return scan;
}

// What a sensor at `mount` reads at each beam angle: from one pose (instantaneous), or with
// beam i measured at beam_time_s[i] while the base moves (swept), as a real head reads.
void Cast(LidarScan* scan, const std::vector<float>& beam_time_s) {
  for (std::size_t i = 0; i < scan->range_m.size(); ++i) {
    const double t = beam_time_s.empty() ? 0.0 : beam_time_s[i];
    const Pose2d sensor = BaseInWorld(t) * scan->sensor_pose;
    const Point2d origin{sensor.x_m, sensor.y_m};
    scan->range_m[i] =
        static_cast<float>(RangeToRoomWalls(origin, sensor.yaw_rad + scan->BeamAngle(i)));
  }
  scan->beam_time_s = beam_time_s;
}

BaseMotion TrueMotion() {
  return [](double t_s) { return BaseInWorld(0.0).Inverse() * BaseInWorld(t_s); };
}

// Errors of the beams with a return against the instantaneous scan, in metres, sorted.
std::vector<double> SortedErrors(const LidarScan& scan, const LidarScan& truth) {
  std::vector<double> errors;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    if (scan.range_m[i] != 0.0f) errors.push_back(std::abs(scan.range_m[i] - truth.range_m[i]));
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

double Percentile(const std::vector<double>& sorted, double p) {
  return sorted[static_cast<std::size_t>(p * (sorted.size() - 1))];
}

TEST(DeskewScan, ASweptScanOfATurningRobotBecomesTheInstantaneousOne) {
  const int num_beams = 720;
  const double period_s = 1.0 / 5.5;  // an RPLidar A1, turning clockwise
  const Pose2d mount{0.1, -0.05, 0.2};
  std::vector<float> beam_time_s(num_beams);
  for (int i = 0; i < num_beams; ++i) beam_time_s[i] = (num_beams - 1 - i) * period_s / num_beams;
  LidarScan swept = EmptyScan(num_beams, 2 * M_PI, mount);
  Cast(&swept, beam_time_s);
  LidarScan instantaneous = EmptyScan(num_beams, 2 * M_PI, mount);
  Cast(&instantaneous, {});

  const LidarScan deskewed = DeskewScan(swept, TrueMotion());
  EXPECT_TRUE(deskewed.beam_time_s.empty());
  EXPECT_EQ(deskewed.utime, swept.utime);
  const std::vector<double> raw_errors = SortedErrors(swept, instantaneous);
  const std::vector<double> errors = SortedErrors(deskewed, instantaneous);
  // A 0.33 rad turn over the sweep: the raw scan is off by metres near the corners.
  EXPECT_GT(Percentile(raw_errors, 0.5), 0.1);
  // Deskewed, what is left is re-binning (end points move up to half a 0.5° beam).
  EXPECT_LT(Percentile(errors, 0.5), 0.01);
  EXPECT_LT(Percentile(errors, 0.95), 0.05);
  // The sweep's two ends overlap by 0.33 rad: bins there get two points, the nearer kept;
  // the bins the turn leaves behind get none. At most that share of beams is empty.
  const auto empty = std::count(deskewed.range_m.begin(), deskewed.range_m.end(), 0.0f);
  EXPECT_LE(empty, num_beams * 0.33 / (2 * M_PI) + 5);
}

TEST(DeskewScan, APartialFieldOfViewKeepsItsBeamsAndDropsWhatTurnsOutOfIt) {
  const int num_beams = 1081;  // a Hokuyo UST-10LX: 270°, counter-clockwise, 25 ms a turn
  const double fov_rad = 1081 * 0.25 * M_PI / 180;
  std::vector<float> beam_time_s(num_beams);
  for (int i = 0; i < num_beams; ++i) beam_time_s[i] = i * 0.025 * 0.25 / 360;
  LidarScan swept = EmptyScan(num_beams, fov_rad, {});
  Cast(&swept, beam_time_s);
  LidarScan instantaneous = EmptyScan(num_beams, fov_rad, {});
  Cast(&instantaneous, {});
  const LidarScan deskewed = DeskewScan(swept, TrueMotion());
  const std::vector<double> errors = SortedErrors(deskewed, instantaneous);
  EXPECT_LT(Percentile(errors, 0.5), 0.01);
  EXPECT_LT(Percentile(errors, 0.9), 0.03);
  EXPECT_GT(Percentile(SortedErrors(swept, instantaneous), 0.9), Percentile(errors, 0.9));
}

TEST(DeskewScan, WithoutMotionOrBeamTimesTheScanIsUnchanged) {
  LidarScan swept = EmptyScan(360, 2 * M_PI, {0.1, 0.0, 0.0});
  std::vector<float> beam_time_s(360);
  for (int i = 0; i < 360; ++i) beam_time_s[i] = i * 0.1f / 360;
  Cast(&swept, {});
  swept.range_m[7] = 0.0f;  // no return stays no return
  swept.beam_time_s = beam_time_s;
  const LidarScan still = DeskewScan(swept, [](double) { return Pose2d{}; });
  for (int i = 0; i < 360; ++i) EXPECT_NEAR(still.range_m[i], swept.range_m[i], 1e-5) << i;
  LidarScan instantaneous = swept;
  instantaneous.beam_time_s.clear();
  EXPECT_EQ(DeskewScan(instantaneous, TrueMotion()).range_m, instantaneous.range_m);
}

}  // namespace
}  // namespace aslam
