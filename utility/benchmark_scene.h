#pragma once

// What the synthetic scenes of the utility benchmarks (spanning_trees_benchmark,
// goal_selector_benchmark) share: SLAM-like edge noise, less certain across
// some direction than along it, and the check that the incremental log dets
// they time are right.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <Eigen/Core>

#include "utility/spanning_trees.h"

namespace aslam {

// Across the edge's direction the translation's standard deviation is this many times larger.
inline constexpr double kAcrossPerAlongSigma = 2.0;

// Information (inverse covariance) over (x_m, y_m, yaw_rad) of an edge whose
// translation error has standard deviation sigma_along_m along the direction
// along_rad, kAcrossPerAlongSigma * sigma_along_m across it, and sigma_yaw_rad in yaw.
inline Eigen::Matrix3d SyntheticEdgeInformation(double sigma_along_m, double sigma_yaw_rad,
                                                double along_rad) {
  Eigen::Matrix3d rotation;
  rotation << std::cos(along_rad), -std::sin(along_rad), 0, std::sin(along_rad),
      std::cos(along_rad), 0, 0, 0, 1;
  const double sigma_across_m = kAcrossPerAlongSigma * sigma_along_m;
  const Eigen::Vector3d variances(sigma_along_m * sigma_along_m, sigma_across_m * sigma_across_m,
                                  sigma_yaw_rad * sigma_yaw_rad);
  // Σ = R diag(variances) Rᵀ, so Σ⁻¹ = R diag(1 / variances) Rᵀ.
  return rotation * variances.cwiseInverse().asDiagonal() * rotation.transpose();
}

// Aborts the benchmark unless the incremental log det of every extension
// equals the one from scratch (CHOLMOD) to 1e-9 relative.
inline void AbortUnlessIncrementalMatchesSparse(const WeightedGraph& graph,
                                                const std::vector<GraphExtension>& extensions,
                                                const char* scene_name) {
  IncrementalLogDet incremental(graph);
  for (const GraphExtension& extension : extensions) {
    const double sparse = LogDetReducedLaplacianSparse(graph, extension);
    const double fast = incremental.LogDet(extension);
    if (std::abs(fast - sparse) > 1e-9 * std::abs(sparse)) {
      std::fprintf(stderr, "%s: incremental %.17g != from scratch %.17g\n", scene_name, fast,
                   sparse);
      std::abort();
    }
  }
}

}  // namespace aslam
