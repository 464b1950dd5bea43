#pragma once

// Pose-graph metrics of docs/architecture.md §6 for the paper's Tables I and II: average
// degree, algebraic connectivity, normalized tree connectivity and the
// evolution of the mean edge D-optimality. Pure C++ on value types, no LCM.
//
// Bad input: an edge whose endpoint is not a node id in [0, number of nodes),
// or a WeightedGraph edge with a negative or non-finite weight, makes every
// function here throw std::invalid_argument naming the edge (index and
// endpoints); such an edge is never skipped silently.

#include <vector>

#include "common/pose_graph.h"
// WeightedGraph, DOptimality, EOptimality, LogDetReducedLaplacianSparse:
#include "utility/spanning_trees.h"

namespace aslam {

// Average degree 2m/n over the graph's edges (every edge counts, odometry and loop closures); 0 for
// no nodes.
double AverageDegree(const PoseGraph& graph);

// Algebraic connectivity: the 2nd-smallest eigenvalue λ2 of the weighted
// Laplacian, edge weight = E-optimality (min eigenvalue) of the edge
// information. 0 for < 2 nodes; exactly 0 for a graph that is disconnected
// once zero-weight edges are dropped. Dense Eigen up to 200 nodes, Spectra
// shift-invert Lanczos above (falls back to dense, with a note on stderr, if
// it does not converge).
double AlgebraicConnectivity(const PoseGraph& graph);
double AlgebraicConnectivity(const WeightedGraph& graph);

// Normalized tree connectivity log det(L̃)/((n−2)·log n), L̃ = weighted
// Laplacian with D-optimality weights, first node's row/column removed.
// NaN for n < 3 or a disconnected graph.
double NormalizedTreeConnectivity(const PoseGraph& graph);
double NormalizedTreeConnectivity(const WeightedGraph& graph);

// Mean D-optimality of the graph's edges; NaN if there is no edge.
double MeanEdgeDOptimality(const PoseGraph& graph);

// Table II of the paper from a series of mean edge D-optimality values over
// time (NaN entries ignored): max, min, difference = max − min,
// percent_reduction = 100·(max − min)/max. All NaN if no finite value
// (non-finite entries count as NaN); percent_reduction is NaN if max is 0.
struct UncertaintyReduction {
  double max = 0, min = 0, difference = 0, percent_reduction = 0;
};
UncertaintyReduction ComputeUncertaintyReduction(const std::vector<double>& mean_edge_d_opt);

}  // namespace aslam
