#include "utility/benchmark_scene.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Dense>

namespace aslam {
namespace {

// The covariance the information inverts, built independently: variance along a unit vector u.
double VarianceAlong(const Eigen::Matrix3d& information, const Eigen::Vector3d& u) {
  return u.dot(information.inverse() * u);
}

TEST(SyntheticEdgeInformation, InvertsTheCovarianceAlongAndAcrossTheDirection) {
  const double sigma_m = 0.03, sigma_yaw_rad = 0.01, along_rad = 0.7;
  const Eigen::Matrix3d information = SyntheticEdgeInformation(sigma_m, sigma_yaw_rad, along_rad);
  const Eigen::Vector3d along(std::cos(along_rad), std::sin(along_rad), 0.0);
  const Eigen::Vector3d across(-std::sin(along_rad), std::cos(along_rad), 0.0);
  const Eigen::Vector3d yaw(0.0, 0.0, 1.0);
  EXPECT_NEAR(std::sqrt(VarianceAlong(information, along)), sigma_m, 1e-12);
  // Twice the standard deviation across: four times the variance.
  EXPECT_NEAR(std::sqrt(VarianceAlong(information, across)), 2.0 * sigma_m, 1e-12);
  EXPECT_NEAR(std::sqrt(VarianceAlong(information, yaw)), sigma_yaw_rad, 1e-12);
  // Along and across are uncorrelated; translation and yaw too.
  const Eigen::Matrix3d covariance = information.inverse();
  EXPECT_NEAR(along.dot(covariance * across), 0.0, 1e-12);
  EXPECT_NEAR(along.dot(covariance * yaw), 0.0, 1e-12);
  EXPECT_NEAR((information - information.transpose()).norm(), 0.0, 1e-9);
}

TEST(SyntheticEdgeInformation, DirectionZeroIsDiagonal) {
  const Eigen::Matrix3d information = SyntheticEdgeInformation(0.1, 0.2, 0.0);
  EXPECT_NEAR(information(0, 0), 1.0 / 0.01, 1e-9);
  EXPECT_NEAR(information(1, 1), 1.0 / 0.04, 1e-9);
  EXPECT_NEAR(information(2, 2), 1.0 / 0.04, 1e-9);
  EXPECT_NEAR(information(0, 1), 0.0, 1e-12);
}

}  // namespace
}  // namespace aslam
