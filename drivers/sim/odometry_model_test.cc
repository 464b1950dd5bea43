#include "drivers/sim/odometry_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace aslam {
namespace {

TEST(OdometryModelTest, DecomposeAndRecompose) {
  const Pose2d forward{0.3, 0.1, 0.25};
  const OdometryMotion m = OdometryModel::Decompose(forward);
  EXPECT_NEAR(m.rot1_rad, std::atan2(0.1, 0.3), 1e-15);
  EXPECT_NEAR(m.trans_m, std::hypot(0.3, 0.1), 1e-15);
  EXPECT_NEAR(m.rot2_rad, 0.25 - std::atan2(0.1, 0.3), 1e-15);
  const Pose2d back = OdometryModel::Recompose(m);
  EXPECT_NEAR(back.x_m, 0.3, 1e-15);
  EXPECT_NEAR(back.y_m, 0.1, 1e-15);
  EXPECT_NEAR(back.yaw_rad, 0.25, 1e-15);

  // Reversing: negative trans, rot1 near 0 rather than near pi.
  const OdometryMotion reverse = OdometryModel::Decompose({-0.2, 0.01, -0.02});
  EXPECT_LT(reverse.trans_m, 0.0);
  EXPECT_NEAR(reverse.rot1_rad, std::atan2(-0.01, 0.2), 1e-15);
  const Pose2d reverse_back = OdometryModel::Recompose(reverse);
  EXPECT_NEAR(reverse_back.x_m, -0.2, 1e-15);
  EXPECT_NEAR(reverse_back.y_m, 0.01, 1e-15);
  EXPECT_NEAR(reverse_back.yaw_rad, -0.02, 1e-15);

  // Turning in place: everything in rot2.
  const OdometryMotion turn = OdometryModel::Decompose({1e-8, -1e-8, 0.4});
  EXPECT_EQ(turn.rot1_rad, 0.0);
  EXPECT_EQ(turn.trans_m, 0.0);
  EXPECT_EQ(turn.rot2_rad, 0.4);
}

TEST(OdometryModelTest, ZeroAlphasGiveTheTrueDeltaExactly) {
  const OdometryModel model(OdometryNoiseOptions{0.0, 0.0, 0.0, 0.0});
  std::mt19937_64 rng(1);
  for (const Pose2d& delta :
       {Pose2d{0.01, 0.0005, 0.02}, Pose2d{-0.01, 0.0, 0.0}, Pose2d{0.0, 0.0, -0.03}}) {
    const Pose2d noisy = model.NoisyDelta(delta, rng);
    EXPECT_EQ(noisy.x_m, delta.x_m);
    EXPECT_EQ(noisy.y_m, delta.y_m);
    EXPECT_EQ(noisy.yaw_rad, delta.yaw_rad);
  }
}

struct Moments {
  double mean = 0.0;
  double variance = 0.0;
};

Moments Measure(const std::vector<double>& samples) {
  Moments m;
  for (double s : samples) m.mean += s;
  m.mean /= samples.size();
  for (double s : samples) m.variance += (s - m.mean) * (s - m.mean);
  m.variance /= samples.size() - 1;
  return m;
}

TEST(OdometryModelTest, NoiseMatchesTheModelVariances) {
  const OdometryNoiseOptions alphas{0.05, 0.02, 0.03, 0.01};
  const OdometryModel model(alphas);
  const Pose2d delta = OdometryModel::Recompose({0.15, 0.2, -0.1});
  std::mt19937_64 rng(2);
  constexpr int kSamples = 20000;
  std::vector<double> rot1_error, trans_error, rot2_error;
  for (int i = 0; i < kSamples; ++i) {
    const OdometryMotion noisy = OdometryModel::Decompose(model.NoisyDelta(delta, rng));
    rot1_error.push_back(noisy.rot1_rad - 0.15);
    trans_error.push_back(noisy.trans_m - 0.2);
    rot2_error.push_back(noisy.rot2_rad + 0.1);
  }
  const double rot1_variance = 0.05 * 0.15 * 0.15 + 0.02 * 0.2 * 0.2;
  const double trans_variance = 0.03 * 0.2 * 0.2 + 0.01 * (0.15 * 0.15 + 0.1 * 0.1);
  const double rot2_variance = 0.05 * 0.1 * 0.1 + 0.02 * 0.2 * 0.2;
  const struct {
    const char* name;
    Moments measured;
    double variance;
  } cases[] = {{"rot1", Measure(rot1_error), rot1_variance},
               {"trans", Measure(trans_error), trans_variance},
               {"rot2", Measure(rot2_error), rot2_variance}};
  for (const auto& c : cases) {
    // Mean within 4 standard errors; sample variance within 5% (its standard error is 1%).
    EXPECT_NEAR(c.measured.mean, 0.0, 4.0 * std::sqrt(c.variance / kSamples)) << c.name;
    EXPECT_NEAR(c.measured.variance, c.variance, 0.05 * c.variance) << c.name;
  }
}

TEST(OdometryModelTest, SameSeedSameNoise) {
  const OdometryModel model{OdometryNoiseOptions{}};
  std::mt19937_64 a(5), b(5);
  for (int i = 0; i < 100; ++i) {
    const Pose2d delta{0.01 * i, 0.001, 0.002 * i};
    const Pose2d na = model.NoisyDelta(delta, a), nb = model.NoisyDelta(delta, b);
    EXPECT_EQ(na.x_m, nb.x_m);
    EXPECT_EQ(na.y_m, nb.y_m);
    EXPECT_EQ(na.yaw_rad, nb.yaw_rad);
  }
}

}  // namespace
}  // namespace aslam
