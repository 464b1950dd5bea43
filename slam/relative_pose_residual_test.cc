#include "slam/relative_pose_residual.h"

#include <cmath>
#include <memory>
#include <random>
#include <tuple>

#include <ceres/jet.h>
#include <gtest/gtest.h>
#include <Eigen/Cholesky>

#include "common/pose2d.h"

namespace aslam {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Independent reference for the residual: built on Pose2d::Between and
// WrapAngle, over the stacked parameters (x_a, y_a, yaw_a, x_b, y_b, yaw_b).
Eigen::Vector3d ReferenceResidual(const Vector6d& p, const Pose2d& measurement,
                                  const Eigen::Matrix3d& sqrt_information) {
  const Pose2d a{p(0), p(1), p(2)};
  const Pose2d b{p(3), p(4), p(5)};
  const Pose2d a_to_b = a.Between(b);
  const Eigen::Vector3d error(a_to_b.x_m - measurement.x_m, a_to_b.y_m - measurement.y_m,
                              WrapAngle(b.yaw_rad - a.yaw_rad - measurement.yaw_rad));
  return sqrt_information * error;
}

// Residual and the 3x6 Jacobian over the stacked parameters, from the cost function.
void Evaluate(const ceres::CostFunction& cost, const Vector6d& p, Eigen::Vector3d* residual,
              Eigen::Matrix<double, 3, 6>* jacobian) {
  const double* parameters[2] = {p.data(), p.data() + 3};
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> j_a, j_b;
  double* jacobians[2] = {j_a.data(), j_b.data()};
  ASSERT_TRUE(cost.Evaluate(parameters, residual->data(), jacobians));
  jacobian->leftCols<3>() = j_a;
  jacobian->rightCols<3>() = j_b;
}

Eigen::Matrix<double, 3, 6> CentralDifferenceJacobian(const Vector6d& p, const Pose2d& measurement,
                                                      const Eigen::Matrix3d& sqrt_information) {
  constexpr double kStep = 1e-6;
  Eigen::Matrix<double, 3, 6> jacobian;
  for (int k = 0; k < 6; ++k) {
    Vector6d plus = p, minus = p;
    plus(k) += kStep;
    minus(k) -= kStep;
    jacobian.col(k) = (ReferenceResidual(plus, measurement, sqrt_information) -
                       ReferenceResidual(minus, measurement, sqrt_information)) /
                      (2.0 * kStep);
  }
  return jacobian;
}

Eigen::Matrix3d RandomSqrtInformation(std::mt19937* rng) {
  std::uniform_real_distribution<double> diag(0.5, 20.0), off(-3.0, 3.0);
  Eigen::Matrix3d u = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    u(i, i) = diag(*rng);
    for (int j = i + 1; j < 3; ++j) u(i, j) = off(*rng);
  }
  return u;
}

void CheckAgainstReference(const Vector6d& p, const Pose2d& measurement,
                           const Eigen::Matrix3d& sqrt_information) {
  std::unique_ptr<ceres::CostFunction> cost(RelativePoseResidual::Create(
      measurement.x_m, measurement.y_m, measurement.yaw_rad, sqrt_information));
  Eigen::Vector3d residual = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 3, 6> jacobian = Eigen::Matrix<double, 3, 6>::Zero();
  Evaluate(*cost, p, &residual, &jacobian);
  const Eigen::Vector3d expected = ReferenceResidual(p, measurement, sqrt_information);
  EXPECT_LT((residual - expected).norm(), 1e-9 * (1.0 + expected.norm()))
      << "params " << p.transpose() << "\nresidual " << residual.transpose() << "\nexpected "
      << expected.transpose();
  const Eigen::Matrix<double, 3, 6> numeric =
      CentralDifferenceJacobian(p, measurement, sqrt_information);
  EXPECT_LT((jacobian - numeric).cwiseAbs().maxCoeff(), 1e-5 * (1.0 + numeric.norm()))
      << "params " << p.transpose() << "\nanalytic\n"
      << jacobian << "\nnumeric\n"
      << numeric;
}

TEST(RelativePoseResidualTest, MatchesReferenceAndCentralDifferencesAtRandomPoses) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(-10.0, 10.0), yaw(-M_PI, M_PI), small(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Vector6d p;
    p << position(rng), position(rng), yaw(rng), position(rng), position(rng), yaw(rng);
    // Keep the yaw error away from ±π, where the wrapped error itself jumps.
    const double yaw_error = 2.5 * small(rng);
    const Pose2d measurement{small(rng) * 3.0, small(rng) * 3.0,
                             WrapAngle(p(5) - p(2) - yaw_error)};
    CheckAgainstReference(p, measurement, RandomSqrtInformation(&rng));
  }
}

TEST(RelativePoseResidualTest, MatchesAcrossTheAngleWrap) {
  std::mt19937 rng(11);
  const Eigen::Matrix3d sqrt_info = RandomSqrtInformation(&rng);
  // Yaws straddling ±π: raw differences are near ±2π, the wrapped error is small.
  const double near_pi = M_PI - 1e-3;
  for (const auto& [yaw_a, yaw_b, yaw_ab] :
       {std::tuple{near_pi, -near_pi, 0.01}, std::tuple{-near_pi, near_pi, -0.01},
        std::tuple{3.1, -3.1, 0.05}, std::tuple{0.2, -0.1, M_PI - 0.2},
        std::tuple{-3.0, 3.0, -M_PI + 0.1}}) {
    Vector6d p;
    p << 1.0, -2.0, yaw_a, 3.0, 0.5, yaw_b;
    CheckAgainstReference(p, Pose2d{0.3, -0.2, yaw_ab}, sqrt_info);
  }
}

TEST(RelativePoseResidualTest, WrappedYawErrorIsSmallNotTwoPi) {
  std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseResidual::Create(0.0, 0.0, 0.05, Eigen::Matrix3d::Identity()));
  const double pose_a[3] = {0.0, 0.0, 3.1}, pose_b[3] = {0.0, 0.0, -3.1};
  const double* parameters[2] = {pose_a, pose_b};
  double residual[3];
  ASSERT_TRUE(cost->Evaluate(parameters, residual, nullptr));
  EXPECT_NEAR(residual[2], -6.2 - 0.05 + 2.0 * M_PI, 1e-12);
}

TEST(RelativePoseResidualTest, SquaredNormIsChiSquareWithTheInformation) {
  // r = U·e with Uᵀ·U = I, so rᵀr = eᵀ·I·e also for a non-diagonal I.
  Eigen::Matrix3d information;
  information << 40.0, 5.0, -2.0, 5.0, 30.0, 3.0, -2.0, 3.0, 80.0;
  const Eigen::Matrix3d sqrt_info = information.llt().matrixU();
  std::unique_ptr<ceres::CostFunction> cost(RelativePoseResidual::Create(1.0, 0.2, 0.1, sqrt_info));
  const double pose_a[3] = {0.0, 0.0, 0.0}, pose_b[3] = {1.1, 0.1, 0.15};
  const double* parameters[2] = {pose_a, pose_b};
  Eigen::Vector3d residual;
  ASSERT_TRUE(cost->Evaluate(parameters, residual.data(), nullptr));
  const Eigen::Vector3d error(0.1, -0.1, 0.05);
  EXPECT_NEAR(residual.squaredNorm(), error.dot(information * error), 1e-12);
}

TEST(WrapAngleJetTest, WrapsToHalfOpenIntervalWithUnitDerivative) {
  EXPECT_NEAR(WrapAngleJet(3.0 * M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(WrapAngleJet(-M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(WrapAngleJet(7.0), 7.0 - 2.0 * M_PI, 1e-12);
  EXPECT_NEAR(WrapAngleJet(-7.0), -7.0 + 2.0 * M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(WrapAngleJet(0.5), 0.5);
  const ceres::Jet<double, 1> x(7.0, 0);
  const ceres::Jet<double, 1> y = WrapAngleJet(x);
  EXPECT_NEAR(y.a, 7.0 - 2.0 * M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(y.v[0], 1.0);
}

}  // namespace
}  // namespace aslam
