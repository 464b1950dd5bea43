#pragma once

// The 2D relative-pose error term of the pose graph.
//
// Node poses are (p, ψ) with p = (x_m, y_m) and ψ = yaw_rad. An edge a → b
// measures the pose of b in the frame of a as (t_ab, ψ_ab). With R(ψ) the 2D
// rotation by ψ and U = sqrt_information (upper-triangular, Uᵀ·U = I_ab, the
// transposed Cholesky factor of the edge's information matrix),
//
//   e = [ R(ψ_a)ᵀ (p_b − p_a) − t_ab ]      (translation error, in frame a)
//       [ wrap(ψ_b − ψ_a − ψ_ab)     ]      (yaw error, wrapped to [−π, π))
//   r = U · e,      so  rᵀ r = eᵀ · I_ab · e  (the edge's chi-square).
//
// Parameter blocks: pose_a[3] and pose_b[3], each (x_m, y_m, yaw_rad), the
// yaw on an angle manifold (pose_graph_optimizer.cc). One block per node, not
// position + yaw blocks: that halves Ceres' per-iteration bookkeeping on a
// 5000-node graph. Derivatives by autodiff; relative_pose_residual_test.cc
// checks them against central differences.

#include <cmath>

#include <ceres/autodiff_cost_function.h>
#include <Eigen/Core>

namespace aslam {

// Wraps to [−π, π) with floor only, so it also works on ceres::Jet (floor has
// zero derivative, hence d wrap(θ)/dθ = 1 everywhere but the cut).
template <typename T>
T WrapAngleJet(const T& angle_rad) {
  using std::floor;
  const T two_pi(2.0 * M_PI);
  return angle_rad - two_pi * floor((angle_rad + T(M_PI)) / two_pi);
}

class RelativePoseResidual {
 public:
  RelativePoseResidual(double dx_m, double dy_m, double dyaw_rad,
                       const Eigen::Matrix3d& sqrt_information)
      : dx_m_(dx_m), dy_m_(dy_m), dyaw_rad_(dyaw_rad), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const pose_a, const T* const pose_b, T* residual_ptr) const {
    using std::cos;
    using std::sin;
    const T c = cos(pose_a[2]), s = sin(pose_a[2]);
    const T dx = pose_b[0] - pose_a[0];
    const T dy = pose_b[1] - pose_a[1];
    Eigen::Matrix<T, 3, 1> error;
    error(0) = c * dx + s * dy - T(dx_m_);
    error(1) = -s * dx + c * dy - T(dy_m_);
    error(2) = WrapAngleJet(pose_b[2] - pose_a[2] - T(dyaw_rad_));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> residual(residual_ptr);
    residual = sqrt_information_.template cast<T>() * error;
    return true;
  }

  // The caller owns the result (ceres::Problem takes ownership by default).
  static ceres::CostFunction* Create(double dx_m, double dy_m, double dyaw_rad,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseResidual, 3, 3, 3>(
        new RelativePoseResidual(dx_m, dy_m, dyaw_rad, sqrt_information));
  }

 private:
  double dx_m_;
  double dy_m_;
  double dyaw_rad_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace aslam
