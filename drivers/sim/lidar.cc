#include "drivers/sim/lidar.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include <opencv2/core.hpp>

namespace aslam {
namespace {

constexpr float kFloatInfinity = std::numeric_limits<float>::infinity();

}  // namespace

LidarModel::LidarModel(const LidarOptions& options) : options_(options) {
  if (options.num_beams < 1) {
    std::fprintf(stderr, "LidarModel: num_beams = %d < 1\n", options.num_beams);
    std::abort();
  }
  beam_cos_.resize(options.num_beams);
  beam_sin_.resize(options.num_beams);
  for (int i = 0; i < options.num_beams; ++i) {
    beam_cos_[i] = std::cos(BeamAngle(i));
    beam_sin_[i] = std::sin(BeamAngle(i));
  }
}

std::vector<double> LidarModel::ExactRanges(const SimWorld& world,
                                            const Pose2d& sensor_pose_in_world) const {
  const double c = std::cos(sensor_pose_in_world.yaw_rad);
  const double s = std::sin(sensor_pose_in_world.yaw_rad);
  std::vector<Point2d> directions(options_.num_beams);
  for (int i = 0; i < options_.num_beams; ++i) {
    // Rotating the precomputed beam direction: two products instead of a sincos.
    directions[i] = {c * beam_cos_[i] - s * beam_sin_[i], s * beam_cos_[i] + c * beam_sin_[i]};
  }
  return world.CastRays({sensor_pose_in_world.x_m, sensor_pose_in_world.y_m}, directions,
                        options_.range_max_m);
}

double LidarModel::ExactRange(const SimWorld& world, const Pose2d& sensor_pose_in_world,
                              int beam) const {
  const double c = std::cos(sensor_pose_in_world.yaw_rad);
  const double s = std::sin(sensor_pose_in_world.yaw_rad);
  const Point2d direction{c * beam_cos_[beam] - s * beam_sin_[beam],
                          s * beam_cos_[beam] + c * beam_sin_[beam]};
  return world.CastRayAlong({sensor_pose_in_world.x_m, sensor_pose_in_world.y_m}, direction,
                            options_.range_max_m);
}

LidarScan LidarModel::Scan(const SimWorld& world, const Pose2d& sensor_pose_in_world, int64_t utime,
                           int64_t seq, std::mt19937_64& rng) const {
  return ScanFromExactRanges(ExactRanges(world, sensor_pose_in_world), utime, seq, rng);
}

LidarScan LidarModel::ScanFromExactRanges(const std::vector<double>& exact, int64_t utime,
                                          int64_t seq, std::mt19937_64& rng) const {
  LidarScan scan;
  scan.utime = utime;
  scan.seq = seq;
  scan.angle_min_rad = options_.angle_min_rad;
  scan.angle_increment_rad = angle_increment_rad();
  scan.range_min_m = options_.range_min_m;
  scan.range_max_m = options_.range_max_m;
  scan.range_m.resize(options_.num_beams);
  // One draw from the caller's stream seeds OpenCV's generator for the beams:
  // its ziggurat normals cost a fifth of std::normal_distribution's.
  cv::RNG beam_rng(rng());
  cv::Mat1d dropout_draws(1, options_.num_beams), noise_draws(1, options_.num_beams);
  beam_rng.fill(dropout_draws, cv::RNG::UNIFORM, 0.0, 1.0);
  beam_rng.fill(noise_draws, cv::RNG::NORMAL, 0.0, 1.0);
  for (int i = 0; i < options_.num_beams; ++i) {
    const double dropout_draw = dropout_draws(0, i);
    const double noise_draw = noise_draws(0, i);
    const double true_range = exact[i];
    double range = 0.0;
    if (true_range <= options_.range_max_m && dropout_draw >= options_.dropout_probability) {
      const double sigma = options_.noise_sigma_m + options_.noise_sigma_fraction * true_range;
      const double noisy = true_range + sigma * noise_draw;
      if (noisy >= options_.range_min_m) range = std::min(noisy, options_.range_max_m);
    }
    float stored = static_cast<float>(range);
    if (range > 0.0) {
      // Rounding to float must not push a valid reading outside [range_min, range_max].
      while (stored < options_.range_min_m) stored = std::nextafter(stored, kFloatInfinity);
      while (stored > options_.range_max_m) stored = std::nextafter(stored, 0.0f);
    }
    scan.range_m[i] = stored;
  }
  return scan;
}

}  // namespace aslam
