#pragma once

// Sparse nonlinear least squares over a 2D pose graph with Ceres
// (SPARSE_NORMAL_CHOLESKY on SuiteSparse): the first node is held constant,
// loop-closure edges go through a robust loss, and the solve is warm-started
// from the poses already in the graph.

#include <string>

#include "common/pose_graph.h"

namespace aslam {

struct PoseGraphOptimizerOptions {
  int max_iterations = 50;
  double function_tolerance = 1e-6;
  // Scale of the Huber loss on loop-closure residuals, in units of the
  // whitened residual (sqrt of chi-square); <= 0 disables the robust loss.
  double loop_closure_loss_scale = 1.0;
  int num_threads = 1;
};

struct OptimizationSummary {
  bool usable = false;  // Ceres reports a usable solution
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double solve_time_s = 0.0;  // Ceres' own total time
  std::string message;        // Ceres' termination message
};

class PoseGraphOptimizer {
 public:
  explicit PoseGraphOptimizer(PoseGraphOptimizerOptions options);

  // Optimizes the node poses of `graph` in place (yaws wrapped afterwards).
  // A graph with fewer than two nodes or no edges is returned unchanged, and
  // so is the graph when Ceres finds no usable solution (`usable` false).
  // Aborts on a broken invariant: non-dense node ids, an edge to a missing
  // node or to itself, a non-finite, asymmetric or non-SPD information matrix.
  OptimizationSummary Optimize(PoseGraph* graph) const;

  const PoseGraphOptimizerOptions& options() const { return options_; }

 private:
  PoseGraphOptimizerOptions options_;
};

// Whitened squared error eᵀ·I·e of one edge at the graph's current poses,
// with e the optimizer's own error (slam/relative_pose_residual.h):
// e = (R(yaw_from)ᵀ(p_to − p_from) − t_measured, wrap(yaw_to − yaw_from − yaw_measured)).
// No robust loss applied, so outlying loop closures stand out.
double EdgeChiSquare(const PoseGraph& graph, const PoseGraphEdge& edge);

}  // namespace aslam
