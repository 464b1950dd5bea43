#include "slam/pose_graph_optimizer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>

#include "slam/relative_pose_residual.h"

namespace aslam {
namespace {

// (x_m, y_m, yaw_rad) with the yaw on the circle: steps are added then the
// yaw wrapped, so yaws stay in [−π, π) during the solve and the tangent space
// is plain R³.
class Pose2dManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    x_plus_delta[0] = x[0] + delta[0];
    x_plus_delta[1] = x[1] + delta[1];
    x_plus_delta[2] = WrapAngleJet(x[2] + delta[2]);
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(jacobian).setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    y_minus_x[0] = y[0] - x[0];
    y_minus_x[1] = y[1] - x[1];
    y_minus_x[2] = WrapAngleJet(y[2] - x[2]);
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(jacobian).setIdentity();
    return true;
  }
};

[[noreturn]] void Die(const char* what, const PoseGraphEdge& edge) {
  std::fprintf(stderr, "PoseGraphOptimizer: %s (edge %d -> %d)\n", what, edge.from_id, edge.to_id);
  std::abort();
}

// Node ids, edge ids and information matrices are the builder's invariants
// (docs/architecture.md §8): a violation is a bug upstream, so abort with a message.
void CheckEdge(const PoseGraph& graph, const PoseGraphEdge& edge) {
  const int n = static_cast<int>(graph.nodes.size());
  if (edge.from_id < 0 || edge.from_id >= n || edge.to_id < 0 || edge.to_id >= n) {
    Die("edge refers to a missing node", edge);
  }
  if (edge.from_id == edge.to_id) Die("edge connects a node to itself", edge);
}

// U with Uᵀ·U = information (U = Lᵀ of the LLT), so ‖U·e‖² = eᵀ·I·e.
Eigen::Matrix3d SqrtInformation(const PoseGraphEdge& edge) {
  const Eigen::Matrix3d& info = edge.information;
  if (!info.allFinite()) Die("information matrix is not finite", edge);
  const double scale = std::max(1.0, info.cwiseAbs().maxCoeff());
  if ((info - info.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    Die("information matrix is not symmetric", edge);
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(info);
  if (llt.info() != Eigen::Success) Die("information matrix is not positive definite", edge);
  return llt.matrixU();
}

void CheckNodeIds(const PoseGraph& graph) {
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    if (graph.nodes[i].id != static_cast<int>(i)) {
      std::fprintf(stderr, "PoseGraphOptimizer: nodes[%zu].id == %d, ids must be dense\n", i,
                   graph.nodes[i].id);
      std::abort();
    }
  }
}

}  // namespace

PoseGraphOptimizer::PoseGraphOptimizer(PoseGraphOptimizerOptions options)
    : options_(std::move(options)) {}

OptimizationSummary PoseGraphOptimizer::Optimize(PoseGraph* graph) const {
  OptimizationSummary result;
  const std::size_t n = graph->nodes.size();
  if (n < 2 || graph->edges.empty()) {
    result.usable = true;
    result.message = "nothing to optimize";
    return result;
  }
  CheckNodeIds(*graph);

  // Warm start: the solver's state is the graph's current estimate.
  std::vector<double> poses(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    poses[3 * i] = graph->nodes[i].pose.x_m;
    poses[3 * i + 1] = graph->nodes[i].pose.y_m;
    poses[3 * i + 2] = WrapAngleJet(graph->nodes[i].pose.yaw_rad);
  }

  // Loss and manifold are shared by many blocks, so the problem must not own
  // them; declared first, they outlive it.
  Pose2dManifold pose_manifold;
  std::unique_ptr<ceres::LossFunction> loop_closure_loss;
  if (options_.loop_closure_loss_scale > 0.0) {
    loop_closure_loss = std::make_unique<ceres::HuberLoss>(options_.loop_closure_loss_scale);
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);

  std::vector<bool> in_problem(n, false);
  for (const PoseGraphEdge& edge : graph->edges) {
    CheckEdge(*graph, edge);
    const int a = edge.from_id, b = edge.to_id;
    for (int id : {a, b}) {
      if (!in_problem[id]) {
        problem.AddParameterBlock(&poses[3 * id], 3, &pose_manifold);
        in_problem[id] = true;
      }
    }
    ceres::LossFunction* loss =
        edge.kind == EdgeKind::kLoopClosure ? loop_closure_loss.get() : nullptr;
    problem.AddResidualBlock(
        RelativePoseResidual::Create(edge.measurement.x_m, edge.measurement.y_m,
                                     edge.measurement.yaw_rad, SqrtInformation(edge)),
        loss, &poses[3 * a], &poses[3 * b]);
  }
  // Gauge: the first node anchors the map frame.
  if (in_problem[0]) problem.SetParameterBlockConstant(&poses[0]);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  solver_options.max_num_iterations = options_.max_iterations;
  solver_options.function_tolerance = options_.function_tolerance;
  solver_options.num_threads = options_.num_threads;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;

  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  result.usable = summary.IsSolutionUsable();
  result.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.solve_time_s = summary.total_time_in_seconds;
  result.message = summary.message;
  if (!result.usable) return result;  // leave the graph as it was

  for (std::size_t i = 0; i < n; ++i) {
    if (!in_problem[i]) continue;
    graph->nodes[i].pose.x_m = poses[3 * i];
    graph->nodes[i].pose.y_m = poses[3 * i + 1];
    graph->nodes[i].pose.yaw_rad = WrapAngle(poses[3 * i + 2]);
  }
  return result;
}

double EdgeChiSquare(const PoseGraph& graph, const PoseGraphEdge& edge) {
  CheckEdge(graph, edge);
  const Pose2d& a = graph.nodes[edge.from_id].pose;
  const Pose2d& b = graph.nodes[edge.to_id].pose;
  const RelativePoseResidual residual(edge.measurement.x_m, edge.measurement.y_m,
                                      edge.measurement.yaw_rad, SqrtInformation(edge));
  const double pose_a[3] = {a.x_m, a.y_m, a.yaw_rad}, pose_b[3] = {b.x_m, b.y_m, b.yaw_rad};
  Eigen::Vector3d r;
  residual(pose_a, pose_b, r.data());
  return r.squaredNorm();
}

}  // namespace aslam
