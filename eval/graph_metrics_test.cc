#include "eval/graph_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace aslam {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Sizes on both sides of the implementation's dense/Spectra switch (200 nodes).
constexpr int kSmall = 12;
constexpr int kLarge = 800;

double RelativeError(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
}

WeightedGraph Path(int n, double weight = 1.0) {
  WeightedGraph graph{n, {}};
  for (int i = 0; i + 1 < n; ++i) graph.edges.push_back({i, i + 1, weight});
  return graph;
}

WeightedGraph Cycle(int n, double weight = 1.0) {
  WeightedGraph graph = Path(n, weight);
  graph.edges.push_back({n - 1, 0, weight});
  return graph;
}

WeightedGraph Complete(int n, double weight = 1.0) {
  WeightedGraph graph{n, {}};
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) graph.edges.push_back({i, j, weight});
  }
  return graph;
}

double PathLambda2(int n) { return 2.0 * (1.0 - std::cos(M_PI / n)); }
double CycleLambda2(int n) { return 2.0 * (1.0 - std::cos(2.0 * M_PI / n)); }

// A pose graph with the same information on every edge, nodes 0..n-1.
PoseGraph ToPoseGraph(const WeightedGraph& shape, const Eigen::Matrix3d& information) {
  PoseGraph graph;
  graph.nodes.resize(shape.num_nodes);
  for (int i = 0; i < shape.num_nodes; ++i) graph.nodes[i].id = i;
  for (const WeightedEdge& edge : shape.edges) {
    PoseGraphEdge pose_edge;
    pose_edge.from_id = edge.from;
    pose_edge.to_id = edge.to;
    pose_edge.kind = edge.to == edge.from + 1 ? EdgeKind::kOdometry : EdgeKind::kLoopClosure;
    pose_edge.information = information;
    graph.edges.push_back(pose_edge);
  }
  return graph;
}

// diag(a, b, c) turned in the x–y plane: not diagonal, same eigenvalues.
Eigen::Matrix3d RotatedInformation(double a, double b, double c) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return rotation * Eigen::Vector3d(a, b, c).asDiagonal() * rotation.transpose();
}

// --- Algebraic connectivity against closed forms ---

TEST(AlgebraicConnectivityTest, PathSmallAndLarge) {
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Path(kSmall)), PathLambda2(kSmall)), 1e-9);
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Path(kLarge)), PathLambda2(kLarge)), 1e-7);
}

TEST(AlgebraicConnectivityTest, CycleSmallAndLarge) {
  // λ2 of a cycle is a double eigenvalue.
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Cycle(kSmall)), CycleLambda2(kSmall)), 1e-9);
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Cycle(kLarge)), CycleLambda2(kLarge)), 1e-7);
}

TEST(AlgebraicConnectivityTest, CompleteGraphIsN) {
  // λ2 = n with multiplicity n − 1: the Krylov space collapses, Lanczos must cope.
  EXPECT_NEAR(AlgebraicConnectivity(Complete(8)), 8.0, 1e-9);
  EXPECT_NEAR(AlgebraicConnectivity(Complete(500)), 500.0, 500.0 * 1e-7);
}

TEST(AlgebraicConnectivityTest, ScalesLinearlyWithTheWeights) {
  const double w = 3.7;
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Path(kSmall, w)), w * PathLambda2(kSmall)), 1e-9);
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Cycle(kLarge, w)), w * CycleLambda2(kLarge)), 1e-7);
  const double tiny = 1e-4;
  EXPECT_LT(RelativeError(AlgebraicConnectivity(Path(kLarge, tiny)), tiny * PathLambda2(kLarge)),
            1e-7);
}

TEST(AlgebraicConnectivityTest, LargeRandomGraphMatchesDenseReference) {
  // Spectra branch against an independent dense solve of the same Laplacian.
  const int n = 400;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> weight(0.5, 20.0);
  std::uniform_int_distribution<int> node(0, n - 1);
  WeightedGraph graph{n, {}};
  for (int i = 0; i + 1 < n; ++i) graph.edges.push_back({i, i + 1, weight(rng)});
  for (int k = 0; k < 150; ++k) graph.edges.push_back({node(rng), node(rng), weight(rng)});
  Eigen::MatrixXd laplacian = Eigen::MatrixXd::Zero(n, n);
  for (const WeightedEdge& e : graph.edges) {
    laplacian(e.from, e.from) += e.weight;
    laplacian(e.to, e.to) += e.weight;
    laplacian(e.from, e.to) -= e.weight;
    laplacian(e.to, e.from) -= e.weight;  // a self-loop adds and removes the same: no effect
  }
  const double expected =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(laplacian, Eigen::EigenvaluesOnly)
          .eigenvalues()[1];
  ASSERT_GT(expected, 1e-3);
  EXPECT_LT(RelativeError(AlgebraicConnectivity(graph), expected), 1e-7);
}

TEST(AlgebraicConnectivityTest, DisconnectedIsZero) {
  for (int half : {kSmall, kLarge}) {
    WeightedGraph two_paths = Path(2 * half);
    two_paths.edges.erase(two_paths.edges.begin() + half - 1);  // the edge half-1 -> half
    EXPECT_EQ(AlgebraicConnectivity(two_paths), 0.0) << half;
    // Joined again by a zero-weight edge: still nothing in the Laplacian between them.
    two_paths.edges.push_back({0, 2 * half - 1, 0.0});
    EXPECT_EQ(AlgebraicConnectivity(two_paths), 0.0) << half;
  }
  // An isolated node among three.
  EXPECT_EQ(AlgebraicConnectivity(WeightedGraph{3, {{0, 1, 1.0}}}), 0.0);
}

TEST(AlgebraicConnectivityTest, FewerThanTwoNodesIsZero) {
  EXPECT_EQ(AlgebraicConnectivity(WeightedGraph{}), 0.0);
  EXPECT_EQ(AlgebraicConnectivity(WeightedGraph{1, {}}), 0.0);
  EXPECT_EQ(AlgebraicConnectivity(PoseGraph{}), 0.0);
}

TEST(AlgebraicConnectivityTest, TwoNodesIsTwiceTheWeight) {
  // L = w·[[1, −1], [−1, 1]]: eigenvalues 0 and 2w.
  EXPECT_NEAR(AlgebraicConnectivity(WeightedGraph{2, {{0, 1, 2.5}}}), 5.0, 1e-12);
}

TEST(AlgebraicConnectivityTest, PoseGraphUsesEOptimalityWeights) {
  const double a = 9.0, b = 4.0, c = 25.0;  // min 4, cube root of the product 6·∛25
  const Eigen::Matrix3d information = RotatedInformation(a, b, c);
  ASSERT_GT(std::abs(information(0, 1)), 0.1);  // really non-diagonal
  EXPECT_LT(RelativeError(AlgebraicConnectivity(ToPoseGraph(Path(kSmall), information)),
                          b * PathLambda2(kSmall)),
            1e-9);
  EXPECT_LT(RelativeError(AlgebraicConnectivity(ToPoseGraph(Cycle(kLarge), information)),
                          b * CycleLambda2(kLarge)),
            1e-7);
}

TEST(AlgebraicConnectivityTest, SingularInformationGivesZeroWeight) {
  // A path whose middle edge has rank-2 information: E-optimality 0, so disconnected.
  PoseGraph graph = ToPoseGraph(Path(6), Eigen::Matrix3d::Identity());
  graph.edges[2].information = RotatedInformation(5.0, 0.0, 3.0);
  EXPECT_EQ(AlgebraicConnectivity(graph), 0.0);
}

// --- Normalized tree connectivity against Kirchhoff's closed forms ---

TEST(NormalizedTreeConnectivityTest, UnitCompleteGraphIsOne) {
  // K_n has n^(n−2) spanning trees: log(n^(n−2))/((n−2)·log n) = 1.
  for (int n : {3, 5, 60}) EXPECT_NEAR(NormalizedTreeConnectivity(Complete(n)), 1.0, 1e-10) << n;
}

TEST(NormalizedTreeConnectivityTest, WeightedCompleteGraph) {
  // Every spanning tree has n − 1 edges of weight w: det = w^(n−1)·n^(n−2).
  for (int n : {4, 40}) {
    for (double w : {0.3, 7.5}) {
      const double expected =
          ((n - 2) * std::log(n) + (n - 1) * std::log(w)) / ((n - 2) * std::log(n));
      EXPECT_NEAR(NormalizedTreeConnectivity(Complete(n, w)), expected, 1e-10) << n << " " << w;
    }
  }
}

TEST(NormalizedTreeConnectivityTest, PathAndCycle) {
  // A path is its only spanning tree (det = w^(n−1)); a cycle has n of them (det = n·w^(n−1)).
  const int n = 50;
  const double w = 2.0;
  const double denominator = (n - 2) * std::log(n);
  EXPECT_NEAR(NormalizedTreeConnectivity(Path(n)), 0.0, 1e-10);
  EXPECT_NEAR(NormalizedTreeConnectivity(Path(n, w)), (n - 1) * std::log(w) / denominator, 1e-10);
  EXPECT_NEAR(NormalizedTreeConnectivity(Cycle(n, w)),
              (std::log(n) + (n - 1) * std::log(w)) / denominator, 1e-10);
}

TEST(NormalizedTreeConnectivityTest, NaNForTinyOrDisconnectedGraphs) {
  EXPECT_TRUE(std::isnan(NormalizedTreeConnectivity(WeightedGraph{})));
  EXPECT_TRUE(std::isnan(NormalizedTreeConnectivity(WeightedGraph{1, {}})));
  EXPECT_TRUE(std::isnan(NormalizedTreeConnectivity(WeightedGraph{2, {{0, 1, 1.0}}})));
  WeightedGraph two_triangles = Complete(3);
  two_triangles.num_nodes = 6;
  for (const WeightedEdge& e : Complete(3).edges)
    two_triangles.edges.push_back({e.from + 3, e.to + 3, 1.0});
  EXPECT_TRUE(std::isnan(NormalizedTreeConnectivity(two_triangles)));
  // Node 0 (the removed row) isolated: the rest alone still has a singular Laplacian.
  WeightedGraph isolated_root = Complete(5);
  isolated_root.edges.erase(std::remove_if(isolated_root.edges.begin(), isolated_root.edges.end(),
                                           [](const WeightedEdge& e) { return e.from == 0; }),
                            isolated_root.edges.end());
  EXPECT_TRUE(std::isnan(NormalizedTreeConnectivity(isolated_root)));
}

TEST(NormalizedTreeConnectivityTest, PoseGraphUsesDOptimalityWeights) {
  const double a = 9.0, b = 4.0, c = 25.0;
  const double w = std::cbrt(a * b * c);
  const int n = 7;
  const double expected = ((n - 2) * std::log(n) + (n - 1) * std::log(w)) / ((n - 2) * std::log(n));
  EXPECT_NEAR(NormalizedTreeConnectivity(ToPoseGraph(Complete(n), RotatedInformation(a, b, c))),
              expected, 1e-10);
}

// --- Average degree and mean edge D-optimality ---

TEST(AverageDegreeTest, CountsEveryEdge) {
  // 5 nodes: odometry 0-1-2-3-4 (4 edges) and 2 loop closures: 2·6/5.
  WeightedGraph shape = Path(5);
  shape.edges.push_back({0, 3, 1.0});
  shape.edges.push_back({1, 4, 1.0});
  const PoseGraph graph = ToPoseGraph(shape, Eigen::Matrix3d::Identity());
  ASSERT_EQ(graph.edges[4].kind, EdgeKind::kLoopClosure);
  EXPECT_DOUBLE_EQ(AverageDegree(graph), 2.4);
  EXPECT_DOUBLE_EQ(AverageDegree(ToPoseGraph(Complete(6), Eigen::Matrix3d::Identity())), 5.0);
  EXPECT_EQ(AverageDegree(PoseGraph{}), 0.0);
  EXPECT_EQ(AverageDegree(ToPoseGraph(WeightedGraph{3, {}}, Eigen::Matrix3d::Identity())), 0.0);
}

TEST(MeanEdgeDOptimalityTest, MeanOfCubeRoots) {
  PoseGraph graph = ToPoseGraph(Path(4), Eigen::Matrix3d::Identity());
  graph.edges[0].information = RotatedInformation(1.0, 8.0, 27.0);           // ∛216 = 6
  graph.edges[1].information = Eigen::Vector3d(2.0, 2.0, 2.0).asDiagonal();  // 2
  graph.edges[2].information = Eigen::Vector3d(4.0, 2.0, 1.0).asDiagonal();  // ∛8 = 2
  EXPECT_NEAR(MeanEdgeDOptimality(graph), 10.0 / 3.0, 1e-12);
}

TEST(MeanEdgeDOptimalityTest, NaNWithoutEdges) {
  EXPECT_TRUE(std::isnan(MeanEdgeDOptimality(PoseGraph{})));
  EXPECT_TRUE(std::isnan(
      MeanEdgeDOptimality(ToPoseGraph(WeightedGraph{3, {}}, Eigen::Matrix3d::Identity()))));
}

// --- Table II ---

TEST(UncertaintyReductionTest, HandSeries) {
  const UncertaintyReduction r = ComputeUncertaintyReduction({kNaN, 4600.0, 3400.0, 3900.0});
  EXPECT_DOUBLE_EQ(r.max, 4600.0);
  EXPECT_DOUBLE_EQ(r.min, 3400.0);
  EXPECT_DOUBLE_EQ(r.difference, 1200.0);
  EXPECT_NEAR(r.percent_reduction, 26.0869565217, 1e-9);  // 1200/4600
}

TEST(UncertaintyReductionTest, AllNaNOrEmpty) {
  for (const std::vector<double>& series :
       {std::vector<double>{kNaN, kNaN}, std::vector<double>{}}) {
    const UncertaintyReduction r = ComputeUncertaintyReduction(series);
    EXPECT_TRUE(std::isnan(r.max));
    EXPECT_TRUE(std::isnan(r.min));
    EXPECT_TRUE(std::isnan(r.difference));
    EXPECT_TRUE(std::isnan(r.percent_reduction));
  }
}

TEST(UncertaintyReductionTest, ConstantSeriesHasNoReduction) {
  const UncertaintyReduction r = ComputeUncertaintyReduction({5.0, kNaN, 5.0});
  EXPECT_EQ(r.max, 5.0);
  EXPECT_EQ(r.min, 5.0);
  EXPECT_EQ(r.difference, 0.0);
  EXPECT_EQ(r.percent_reduction, 0.0);
}

// --- Bad input ---

TEST(GraphMetricsInputTest, EdgeToAMissingNodeThrowsNamingIt) {
  PoseGraph graph = ToPoseGraph(Path(4), Eigen::Matrix3d::Identity());
  graph.edges.push_back({});
  graph.edges.back().from_id = 1;
  graph.edges.back().to_id = 4;
  EXPECT_THROW(AverageDegree(graph), std::invalid_argument);
  EXPECT_THROW(AlgebraicConnectivity(graph), std::invalid_argument);
  EXPECT_THROW(NormalizedTreeConnectivity(graph), std::invalid_argument);
  EXPECT_THROW(MeanEdgeDOptimality(graph), std::invalid_argument);
  try {
    AverageDegree(graph);
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("edge 3 (1 -> 4)"), std::string::npos) << error.what();
  }
  EXPECT_THROW(AlgebraicConnectivity(WeightedGraph{3, {{0, -1, 1.0}}}), std::invalid_argument);
  EXPECT_THROW(NormalizedTreeConnectivity(WeightedGraph{3, {{0, 3, 1.0}}}), std::invalid_argument);
}

TEST(GraphMetricsInputTest, BadWeightOrInformationThrows) {
  EXPECT_THROW(AlgebraicConnectivity(WeightedGraph{3, {{0, 1, 1.0}, {1, 2, -0.5}}}),
               std::invalid_argument);
  EXPECT_THROW(NormalizedTreeConnectivity(WeightedGraph{3, {{0, 1, kNaN}, {1, 2, 1.0}}}),
               std::invalid_argument);
  PoseGraph graph = ToPoseGraph(Path(3), Eigen::Matrix3d::Identity());
  graph.edges[1].information = Eigen::Vector3d(1.0, -2.0, 1.0).asDiagonal();
  EXPECT_THROW(AlgebraicConnectivity(graph), std::invalid_argument);
}

}  // namespace
}  // namespace aslam
