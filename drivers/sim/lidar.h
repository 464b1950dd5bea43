#pragma once

// A simulated planar lidar: exact ranges from the world plus Gaussian range
// noise, dropouts and the range limits of a real sensor.

#include <cstdint>
#include <random>
#include <vector>

#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "drivers/sim/sim_world.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

class LidarModel {
 public:
  // Aborts on num_beams < 1: options are validated at load time.
  explicit LidarModel(const LidarOptions& options);

  const LidarOptions& options() const { return options_; }
  int num_beams() const { return options_.num_beams; }
  double angle_increment_rad() const { return options_.fov_rad / options_.num_beams; }
  double BeamAngle(int beam) const { return options_.angle_min_rad + beam * angle_increment_rad(); }

  // Noiseless distances along each beam to the first solid cell, or
  // SimWorld::kNoHit where nothing lies within range_max_m.
  std::vector<double> ExactRanges(const SimWorld& world, const Pose2d& sensor_pose_in_world) const;

  // One sweep from the true ranges plus noise with sigma = noise_sigma_m +
  // noise_sigma_fraction * range. Range 0 means no return: nothing within
  // range_max_m, a dropout, or a noisy reading below range_min_m; noisy
  // ranges are clamped to range_max_m. sensor_pose is left zero: the caller
  // sets the mount (the sensor in the base frame). Takes exactly one number
  // from `rng`, which seeds a cv::RNG that draws one uniform (dropout) per
  // beam, then one normal per beam, whatever the geometry: a seed fixes the
  // output bit for bit.
  LidarScan Scan(const SimWorld& world, const Pose2d& sensor_pose_in_world, int64_t utime,
                 int64_t seq, std::mt19937_64& rng) const;
  // The same sweep from exact ranges gathered beam by beam (a swept scan, each beam cast
  // from the pose at its own time with ExactRange); draws from `rng` as Scan does.
  LidarScan ScanFromExactRanges(const std::vector<double>& exact, int64_t utime, int64_t seq,
                                std::mt19937_64& rng) const;
  // ExactRanges' value for one beam.
  double ExactRange(const SimWorld& world, const Pose2d& sensor_pose_in_world, int beam) const;

  // A swept sensor's timing: the beam measured k-th (k = 0 first) and its time after the
  // sweep's start. Beams lie one angle increment apart at the head's turn rate.
  int BeamMeasuredAt(int k) const { return options_.clockwise ? options_.num_beams - 1 - k : k; }
  double SweepTimeOfS(int k) const {
    return k * angle_increment_rad() / (2.0 * M_PI * options_.rate_hz);
  }

 private:
  LidarOptions options_;
  // Beam directions in the sensor frame, computed once.
  std::vector<double> beam_cos_;
  std::vector<double> beam_sin_;
};

}  // namespace aslam
