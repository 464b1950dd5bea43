#pragma once

// U1 of docs/architecture.md §5: the weighted number of spanning trees of the pose graph
// extended by a hallucinated path to a frontier, via log det of the reduced
// weighted Laplacian. Three ways to get log det: dense (Eigen, tests and the
// benchmark), sparse from scratch (CHOLMOD, one factorization per candidate),
// and incremental (one CHOLMOD factorization per decision, then a Schur
// complement per candidate from cached forward solves).

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "common/pose_graph.h"

namespace aslam {

// Modern D-optimality of a 3x3 information matrix: exp((1/3)·Σ log λ_k) over
// the eigenvalues λ_k > 1e-8, as docs/architecture.md §5 and the AGS authors' code (skipped
// eigenvalues still count in the 1/3); 0 when there is none.
double DOptimality(const Eigen::Matrix3d& information);
// Min eigenvalue (E-optimality), for the metrics.
double EOptimality(const Eigen::Matrix3d& information);

struct WeightedEdge {
  int from = 0;
  int to = 0;
  double weight = 0.0;
};

struct WeightedGraph {
  int num_nodes = 0;
  std::vector<WeightedEdge> edges;
};

// The pose graph with D-optimality edge weights.
WeightedGraph ToWeightedGraph(const PoseGraph& graph);

// New nodes (numbered num_nodes, num_nodes+1, ... after the base graph) and the
// edges that attach them (to base nodes or among themselves).
struct GraphExtension {
  int num_new_nodes = 0;
  std::vector<WeightedEdge> edges;
};

// log det of the Laplacian of base ∪ extension with node 0's row and column removed.
double LogDetReducedLaplacianDense(const WeightedGraph& base, const GraphExtension& extension = {});
double LogDetReducedLaplacianSparse(const WeightedGraph& base,
                                    const GraphExtension& extension = {});

// U1 = n^(1/n) · exp(log det / n), n = number of vertices.
double U1FromLogDet(double log_det, int num_nodes);

// One CHOLMOD factorization of the base graph's reduced Laplacian; then
// LogDet(extension) for many extensions via the Schur complement of the new
// nodes' block, caching the solves for base nodes shared across extensions.
// Equal to LogDetReducedLaplacianSparse(base, extension) to 1e-9 relative.
class IncrementalLogDet {
 public:
  // Aborts if the base graph is not connected (its reduced Laplacian is not SPD).
  explicit IncrementalLogDet(const WeightedGraph& base);
  ~IncrementalLogDet();
  IncrementalLogDet(const IncrementalLogDet&) = delete;
  IncrementalLogDet& operator=(const IncrementalLogDet&) = delete;

  double base_log_det() const;
  double LogDet(const GraphExtension& extension);
  int cached_solves() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aslam
