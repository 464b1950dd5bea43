#include "utility/spanning_trees.h"

#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace aslam {
namespace {

// Kirchhoff by brute force: the sum over every spanning tree of the product of
// its edge weights (subsets of num_nodes − 1 edges without a cycle).
double BruteForceWeightedTreeCount(int num_nodes, const std::vector<WeightedEdge>& edges) {
  const int m = static_cast<int>(edges.size());
  double total = 0.0;
  for (unsigned mask = 0; mask < (1u << m); ++mask) {
    if (__builtin_popcount(mask) != num_nodes - 1) continue;
    std::vector<int> parent(num_nodes);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int v) {
      while (parent[v] != v) v = parent[v];
      return v;
    };
    bool acyclic = true;
    double product = 1.0;
    for (int e = 0; e < m && acyclic; ++e) {
      if (!(mask & (1u << e))) continue;
      const int a = find(edges[e].from), b = find(edges[e].to);
      if (a == b) acyclic = false;
      parent[a] = b;
      product *= edges[e].weight;
    }
    if (acyclic) total += product;
  }
  return total;
}

double RelativeError(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
}

TEST(DOptimalityTest, DiagonalIsCubeRootOfProduct) {
  // diag(2, 4, 8): (2·4·8)^(1/3) = 64^(1/3) = 4.
  EXPECT_NEAR(DOptimality(Eigen::Vector3d(2, 4, 8).asDiagonal()), 4.0, 1e-12);
  // diag(400, 400, 2500): (4e8)^(1/3) = 736.806...
  EXPECT_NEAR(DOptimality(Eigen::Vector3d(400, 400, 2500).asDiagonal()), std::cbrt(4e8), 1e-9);
}

TEST(DOptimalityTest, RotatedDiagonalHasTheSameValue) {
  // R·diag(2, 4, 8)·Rᵀ is not diagonal but has the same eigenvalues: still 4.
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d information =
      rotation * Eigen::Vector3d(2, 4, 8).asDiagonal() * rotation.transpose();
  ASSERT_GT(std::abs(information(0, 1)), 0.1);  // really non-diagonal
  EXPECT_NEAR(DOptimality(information), 4.0, 1e-12);
  EXPECT_NEAR(EOptimality(information), 2.0, 1e-12);
}

TEST(DOptimalityTest, EigenvaluesAtOrBelowFloorAreSkipped) {
  // diag(8, 27, 0): exp((log 8 + log 27)/3) = (8·27)^(1/3) = 6 (the 1/3 stays, docs/architecture.md
  // §5).
  EXPECT_NEAR(DOptimality(Eigen::Vector3d(8, 27, 0).asDiagonal()), 6.0, 1e-12);
  // 1e-9 <= 1e-8: skipped as well, not log(1e-9).
  EXPECT_NEAR(DOptimality(Eigen::Vector3d(8, 27, 1e-9).asDiagonal()), 6.0, 1e-12);
  EXPECT_EQ(DOptimality(Eigen::Matrix3d::Zero()), 0.0);
}

TEST(DOptimalityTest, RotatedSingularMatrixStillSkipsItsZeroEigenvalue) {
  // R·diag(8, 27, 0)·Rᵀ: no zero on the diagonal, yet one eigenvalue is 0: still 6.
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(3, -1, 2).normalized()).toRotationMatrix();
  const Eigen::Matrix3d information =
      rotation * Eigen::Vector3d(8, 27, 0).asDiagonal() * rotation.transpose();
  EXPECT_NEAR(DOptimality(information), 6.0, 1e-9);
}

TEST(DOptimalityTest, AgreesWithTheEigenvaluesOnEdgeLikeInformation) {
  // Information as edges carry it: translation 1e2..1e6, rotation 1e1..1e5, correlated.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> log10_scale(1.0, 6.0), angle(-M_PI, M_PI);
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Vector3d eigenvalues(std::pow(10.0, log10_scale(random)),
                                      std::pow(10.0, log10_scale(random)),
                                      std::pow(10.0, log10_scale(random)));
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(angle(random),
                          Eigen::Vector3d(angle(random), angle(random), angle(random)).normalized())
            .toRotationMatrix();
    const Eigen::Matrix3d information = rotation * eigenvalues.asDiagonal() * rotation.transpose();
    const double expected = std::cbrt(eigenvalues.prod());
    EXPECT_LT(RelativeError(DOptimality(information), expected), 1e-9) << "trial " << trial;
  }
}

TEST(EOptimalityTest, MinEigenvalue) {
  EXPECT_NEAR(EOptimality(Eigen::Vector3d(5, 3, 9).asDiagonal()), 3.0, 1e-12);
}

TEST(ToWeightedGraphTest, DOptimalityWeightsAndEndpoints) {
  PoseGraph graph;
  graph.nodes.resize(3);
  for (int i = 0; i < 3; ++i) graph.nodes[i].id = i;
  PoseGraphEdge a;
  a.from_id = 0;
  a.to_id = 1;
  a.information = Eigen::Vector3d(2, 4, 8).asDiagonal();
  PoseGraphEdge b;
  b.from_id = 2;
  b.to_id = 0;
  b.kind = EdgeKind::kLoopClosure;
  b.information = Eigen::Vector3d(1, 1, 27).asDiagonal();
  graph.edges = {a, b};
  const WeightedGraph weighted = ToWeightedGraph(graph);
  ASSERT_EQ(weighted.num_nodes, 3);
  ASSERT_EQ(weighted.edges.size(), 2u);
  EXPECT_EQ(weighted.edges[0].from, 0);
  EXPECT_EQ(weighted.edges[0].to, 1);
  EXPECT_NEAR(weighted.edges[0].weight, 4.0, 1e-12);
  EXPECT_EQ(weighted.edges[1].from, 2);
  EXPECT_EQ(weighted.edges[1].to, 0);
  EXPECT_NEAR(weighted.edges[1].weight, 3.0, 1e-12);
}

// All three log-det routes on one graph, split as base + extension for the incremental one.
void ExpectAllRoutes(const WeightedGraph& whole, const WeightedGraph& base,
                     const GraphExtension& extension, double expected_det) {
  EXPECT_NEAR(LogDetReducedLaplacianDense(whole), std::log(expected_det), 1e-12);
  EXPECT_NEAR(LogDetReducedLaplacianSparse(whole), std::log(expected_det), 1e-12);
  EXPECT_NEAR(LogDetReducedLaplacianDense(base, extension), std::log(expected_det), 1e-12);
  EXPECT_NEAR(LogDetReducedLaplacianSparse(base, extension), std::log(expected_det), 1e-12);
  IncrementalLogDet incremental(base);
  EXPECT_NEAR(incremental.LogDet(extension), std::log(expected_det), 1e-12);
}

TEST(KirchhoffTest, WeightedFourCycle) {
  // Cycle 0-1-2-3-0 with weights 1, 2, 3, 4: each spanning tree drops one edge,
  // so the count is 2·3·4 + 1·3·4 + 1·2·4 + 1·2·3 = 24 + 12 + 8 + 6 = 50.
  const std::vector<WeightedEdge> edges = {{0, 1, 1.0}, {1, 2, 2.0}, {2, 3, 3.0}, {3, 0, 4.0}};
  ASSERT_DOUBLE_EQ(BruteForceWeightedTreeCount(4, edges), 50.0);
  const WeightedGraph whole{4, edges};
  // Base: the path 0-1-2 (det 1·2 = 2); extension: node 3 closing the cycle.
  const WeightedGraph base{3, {edges[0], edges[1]}};
  const GraphExtension extension{1, {edges[2], edges[3]}};
  ExpectAllRoutes(whole, base, extension, 50.0);
  // U1 = n^(1/n)·det^(1/n) = (4·50)^(1/4).
  EXPECT_NEAR(U1FromLogDet(std::log(50.0), 4), std::pow(200.0, 0.25), 1e-12);
}

TEST(KirchhoffTest, WeightedK4) {
  const std::vector<WeightedEdge> edges = {{0, 1, 1.0}, {0, 2, 2.0}, {0, 3, 3.0},
                                           {1, 2, 4.0}, {1, 3, 5.0}, {2, 3, 6.0}};
  const double count = BruteForceWeightedTreeCount(4, edges);
  // Unweighted K4 has 4^(4−2) = 16 trees (Cayley): the brute force agrees.
  std::vector<WeightedEdge> unit = edges;
  for (WeightedEdge& e : unit) e.weight = 1.0;
  ASSERT_DOUBLE_EQ(BruteForceWeightedTreeCount(4, unit), 16.0);
  const WeightedGraph whole{4, edges};
  // Base: nodes 0, 1, 2 (a triangle); extension: node 3 with edges to all three.
  const WeightedGraph base{3, {edges[0], edges[1], edges[3]}};
  const GraphExtension extension{1, {edges[2], edges[4], edges[5]}};
  ExpectAllRoutes(whole, base, extension, count);
  // Base 0-1 only; two new nodes with edges to the root (diagonal only), to
  // node 1 and between themselves.
  const WeightedGraph small_base{2, {edges[0]}};
  const GraphExtension two_new{2, {edges[1], edges[2], edges[3], edges[4], edges[5]}};
  ExpectAllRoutes(whole, small_base, two_new, count);
}

TEST(KirchhoffTest, ParallelEdgesAdd) {
  // Path 0-1-2 with edge 1-2 doubled (2 + 3): the trees are {01, 12a} and {01, 12b}: 1·2 + 1·3 = 5.
  const std::vector<WeightedEdge> edges = {{0, 1, 1.0}, {1, 2, 2.0}, {2, 1, 3.0}};
  ASSERT_DOUBLE_EQ(BruteForceWeightedTreeCount(3, edges), 5.0);
  const WeightedGraph whole{3, edges};
  const WeightedGraph base{3, {edges[0], edges[1]}};
  // An extension may hold edges between base nodes only (no new nodes).
  const GraphExtension extension{0, {edges[2]}};
  ExpectAllRoutes(whole, base, extension, 5.0);
}

TEST(LogDetTest, DisconnectedGraphHasNoSpanningTree) {
  const WeightedGraph base{3, {{0, 1, 1.0}, {1, 2, 1.0}}};
  const GraphExtension isolated{1, {}};
  const double minus_inf = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(LogDetReducedLaplacianDense(base, isolated), minus_inf);
  EXPECT_EQ(LogDetReducedLaplacianSparse(base, isolated), minus_inf);
  IncrementalLogDet incremental(base);
  EXPECT_EQ(incremental.LogDet(isolated), minus_inf);
  EXPECT_EQ(U1FromLogDet(minus_inf, 4), 0.0);
}

TEST(LogDetDeathTest, IncrementalAbortsOnDisconnectedBase) {
  const WeightedGraph base{3, {{0, 1, 1.0}}};
  EXPECT_DEATH(IncrementalLogDet{base}, "not connected");
}

TEST(LogDetTest, SingleNodeBase) {
  // Base is the root alone (empty A): the extension's block is everything.
  const WeightedGraph base{1, {}};
  const GraphExtension extension{2, {{0, 1, 2.0}, {1, 2, 3.0}}};
  IncrementalLogDet incremental(base);
  EXPECT_EQ(incremental.base_log_det(), 0.0);
  EXPECT_NEAR(incremental.LogDet(extension), std::log(6.0), 1e-12);
}

// SLAM-shaped random graph: a chain with loop closures between nodes up to
// `span` apart, D-optimality-like weights spanning two decades.
WeightedGraph RandomGraph(int num_nodes, double closure_ratio, std::mt19937* rng) {
  std::uniform_real_distribution<double> weight(10.0, 1000.0);
  WeightedGraph graph;
  graph.num_nodes = num_nodes;
  for (int i = 1; i < num_nodes; ++i) graph.edges.push_back({i - 1, i, weight(*rng)});
  const int num_closures = static_cast<int>(closure_ratio * num_nodes);
  std::uniform_int_distribution<int> node(0, num_nodes - 1);
  std::uniform_int_distribution<int> offset(2, 200);
  for (int c = 0; c < num_closures; ++c) {
    const int i = node(*rng);
    const int j = std::max(0, i - offset(*rng));
    if (i != j) graph.edges.push_back({i, j, 0.1 * weight(*rng)});
  }
  return graph;
}

// 1–5 new nodes chained to the newest node, closures to random old nodes
// (node 0 included now and then), sometimes an edge between two old nodes.
GraphExtension RandomExtension(int num_base, std::mt19937* rng) {
  std::uniform_real_distribution<double> weight(1.0, 1000.0);
  std::uniform_int_distribution<int> new_count(1, 5), closures(0, 3), old(0, num_base - 1);
  std::bernoulli_distribution coin(0.2);
  GraphExtension extension;
  extension.num_new_nodes = new_count(*rng);
  for (int k = 0; k < extension.num_new_nodes; ++k) {
    const int i = num_base + k;
    extension.edges.push_back({i - 1, i, weight(*rng)});
    const int c = closures(*rng);
    for (int l = 0; l < c; ++l) extension.edges.push_back({i, old(*rng), weight(*rng)});
    if (coin(*rng)) extension.edges.push_back({0, i, weight(*rng)});
  }
  if (coin(*rng)) extension.edges.push_back({old(*rng), old(*rng), weight(*rng)});
  return extension;
}

TEST(IncrementalLogDetTest, EqualsDenseAndSparseOnSmallRandomGraphs) {
  std::mt19937 rng(7);
  for (int num_nodes : {2, 3, 5, 10, 40, 150}) {
    const WeightedGraph base = RandomGraph(num_nodes, 0.1, &rng);
    IncrementalLogDet incremental(base);
    EXPECT_LT(RelativeError(incremental.base_log_det(), LogDetReducedLaplacianDense(base)), 1e-11);
    for (int trial = 0; trial < 20; ++trial) {
      const GraphExtension extension = RandomExtension(num_nodes, &rng);
      const double dense = LogDetReducedLaplacianDense(base, extension);
      const double sparse = LogDetReducedLaplacianSparse(base, extension);
      const double fast = incremental.LogDet(extension);
      EXPECT_LT(RelativeError(sparse, dense), 1e-11) << num_nodes << " nodes, trial " << trial;
      EXPECT_LT(RelativeError(fast, dense), 1e-11) << num_nodes << " nodes, trial " << trial;
    }
  }
}

TEST(IncrementalLogDetTest, EqualsSparseFromScratchUpTo5000Nodes) {
  std::mt19937 rng(11);
  for (int num_nodes : {500, 2000, 5000}) {
    const WeightedGraph base = RandomGraph(num_nodes, 0.1, &rng);
    IncrementalLogDet incremental(base);
    const double sparse_base = LogDetReducedLaplacianSparse(base);
    EXPECT_LT(RelativeError(incremental.base_log_det(), sparse_base), 1e-9);
    for (int trial = 0; trial < 25; ++trial) {
      const GraphExtension extension = RandomExtension(num_nodes, &rng);
      const double sparse = LogDetReducedLaplacianSparse(base, extension);
      const double fast = incremental.LogDet(extension);
      ASSERT_TRUE(std::isfinite(sparse));
      EXPECT_LT(RelativeError(fast, sparse), 1e-9) << num_nodes << " nodes, trial " << trial;
      // The gain over the base (what ranks frontiers) agrees in absolute terms too.
      EXPECT_NEAR(fast - incremental.base_log_det(), sparse - sparse_base, 1e-8)
          << num_nodes << " nodes, trial " << trial;
    }
  }
}

TEST(IncrementalLogDetTest, CachesOneSolvePerTouchedOldNode) {
  const WeightedGraph base{5, {{0, 1, 1.0}, {1, 2, 2.0}, {2, 3, 3.0}, {3, 4, 4.0}}};
  IncrementalLogDet incremental(base);
  EXPECT_EQ(incremental.cached_solves(), 0);
  // Touches node 4 only.
  incremental.LogDet({1, {{4, 5, 1.0}}});
  EXPECT_EQ(incremental.cached_solves(), 1);
  // Touches 4 (cached) and 2 (new); node 0 is not in the reduced system.
  incremental.LogDet({2, {{4, 5, 1.0}, {5, 6, 1.0}, {6, 2, 1.0}, {6, 0, 1.0}}});
  EXPECT_EQ(incremental.cached_solves(), 2);
}

}  // namespace
}  // namespace aslam
