#pragma once

// Wheel-odometry noise: Thrun's odometry motion model (Probabilistic
// Robotics, table 5.6) applied to the true motion between two samples.

#include <random>

#include "common/pose2d.h"
#include "drivers/sim/simulator_options.h"

namespace aslam {

// A relative motion as rotate, translate, rotate.
struct OdometryMotion {
  double rot1_rad = 0.0;
  double trans_m = 0.0;  // negative when driving backwards
  double rot2_rad = 0.0;
};

class OdometryModel {
 public:
  // Below this translation the heading of the motion is undefined: rot1 = 0.
  static constexpr double kMinTranslationM = 1e-6;

  explicit OdometryModel(const OdometryNoiseOptions& options);

  const OdometryNoiseOptions& options() const { return options_; }

  // Splits a delta (in the earlier pose's frame) into rot1, trans, rot2.
  // Backward motion gets a negative trans and a small rot1 instead of
  // rot1 = ±pi, so reversing is not charged the noise of a half turn.
  static OdometryMotion Decompose(const Pose2d& delta);
  static Pose2d Recompose(const OdometryMotion& motion);

  // The noisy delta the wheels report for `true_delta`: rot1, trans, rot2
  // each get zero-mean Gaussian noise with variance
  //   rot1: a1*rot1^2 + a2*trans^2,  rot2: a1*rot2^2 + a2*trans^2,
  //   trans: a3*trans^2 + a4*(rot1^2 + rot2^2).
  // Always draws three normals (rot1, trans, rot2 in that order); with all
  // alphas 0 it returns true_delta unchanged.
  Pose2d NoisyDelta(const Pose2d& true_delta, std::mt19937_64& rng) const;

 private:
  OdometryNoiseOptions options_;
};

}  // namespace aslam
