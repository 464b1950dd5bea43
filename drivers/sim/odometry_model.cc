#include "drivers/sim/odometry_model.h"

#include <cmath>

namespace aslam {

OdometryModel::OdometryModel(const OdometryNoiseOptions& options) : options_(options) {}

OdometryMotion OdometryModel::Decompose(const Pose2d& delta) {
  OdometryMotion motion;
  const double trans_m = std::hypot(delta.x_m, delta.y_m);
  if (trans_m < kMinTranslationM) {
    motion.rot2_rad = delta.yaw_rad;
    return motion;
  }
  const bool backwards = delta.x_m < 0.0;
  motion.trans_m = backwards ? -trans_m : trans_m;
  motion.rot1_rad =
      backwards ? std::atan2(-delta.y_m, -delta.x_m) : std::atan2(delta.y_m, delta.x_m);
  motion.rot2_rad = WrapAngle(delta.yaw_rad - motion.rot1_rad);
  return motion;
}

Pose2d OdometryModel::Recompose(const OdometryMotion& motion) {
  return {motion.trans_m * std::cos(motion.rot1_rad), motion.trans_m * std::sin(motion.rot1_rad),
          WrapAngle(motion.rot1_rad + motion.rot2_rad)};
}

Pose2d OdometryModel::NoisyDelta(const Pose2d& true_delta, std::mt19937_64& rng) const {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double rot1_draw = normal(rng);
  const double trans_draw = normal(rng);
  const double rot2_draw = normal(rng);
  if (options_.alpha1 == 0.0 && options_.alpha2 == 0.0 && options_.alpha3 == 0.0 &&
      options_.alpha4 == 0.0) {
    return true_delta;  // no round trip through rot/trans/rot: noiseless means exact
  }
  const OdometryMotion m = Decompose(true_delta);
  const double rot1_sq = m.rot1_rad * m.rot1_rad;
  const double rot2_sq = m.rot2_rad * m.rot2_rad;
  const double trans_sq = m.trans_m * m.trans_m;
  OdometryMotion noisy;
  noisy.rot1_rad =
      m.rot1_rad + std::sqrt(options_.alpha1 * rot1_sq + options_.alpha2 * trans_sq) * rot1_draw;
  noisy.trans_m =
      m.trans_m +
      std::sqrt(options_.alpha3 * trans_sq + options_.alpha4 * (rot1_sq + rot2_sq)) * trans_draw;
  noisy.rot2_rad =
      m.rot2_rad + std::sqrt(options_.alpha1 * rot2_sq + options_.alpha2 * trans_sq) * rot2_draw;
  return Recompose(noisy);
}

}  // namespace aslam
