#include "slam/pose_graph_optimizer.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace aslam {
namespace {

PoseGraphEdge MakeEdge(const PoseGraph& graph, int from, int to, EdgeKind kind,
                       const Eigen::Matrix3d& information = Eigen::Matrix3d::Identity() * 100.0) {
  PoseGraphEdge edge;
  edge.from_id = from;
  edge.to_id = to;
  edge.kind = kind;
  edge.measurement = graph.nodes[from].pose.Between(graph.nodes[to].pose);
  edge.information = information;
  return edge;
}

PoseGraph NodesAt(const std::vector<Pose2d>& poses) {
  PoseGraph graph;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    graph.nodes.push_back({static_cast<int>(i), static_cast<int64_t>(i), poses[i]});
  }
  return graph;
}

void ExpectPoseNear(const Pose2d& actual, const Pose2d& expected, double tolerance) {
  EXPECT_NEAR(actual.x_m, expected.x_m, tolerance);
  EXPECT_NEAR(actual.y_m, expected.y_m, tolerance);
  EXPECT_NEAR(WrapAngle(actual.yaw_rad - expected.yaw_rad), 0.0, tolerance);
}

// A unit square driven counter-clockwise; node 2 faces yaw π, node 3 −π/2.
PoseGraph SquareLoop() {
  PoseGraph graph = NodesAt({{0, 0, 0}, {1, 0, M_PI / 2}, {1, 1, M_PI}, {0, 1, -M_PI / 2}});
  for (int i = 0; i < 3; ++i) graph.edges.push_back(MakeEdge(graph, i, i + 1, EdgeKind::kOdometry));
  graph.edges.push_back(MakeEdge(graph, 3, 0, EdgeKind::kLoopClosure));
  return graph;
}

PoseGraphOptimizerOptions TightOptions() {
  PoseGraphOptimizerOptions options;
  options.function_tolerance = 1e-12;
  return options;
}

TEST(PoseGraphOptimizerTest, ConsistentSquareConvergesToExactPosesFromPerturbedStart) {
  const PoseGraph truth = SquareLoop();
  PoseGraph graph = truth;
  graph.nodes[1].pose = {1.3, -0.2, 1.2};
  graph.nodes[2].pose = {0.7, 1.4, -2.8};  // yaw on the other side of ±π
  graph.nodes[3].pose = {-0.3, 0.8, -1.2};
  const OptimizationSummary summary = PoseGraphOptimizer(TightOptions()).Optimize(&graph);
  ASSERT_TRUE(summary.usable) << summary.message;
  EXPECT_GT(summary.initial_cost, 1.0);
  EXPECT_LT(summary.final_cost, 1e-12);
  for (std::size_t i = 0; i < truth.nodes.size(); ++i) {
    ExpectPoseNear(graph.nodes[i].pose, truth.nodes[i].pose, 1e-6);
    EXPECT_GT(graph.nodes[i].pose.yaw_rad, -M_PI);  // wrapped to (−π, π]
    EXPECT_LE(graph.nodes[i].pose.yaw_rad, M_PI);
  }
}

TEST(PoseGraphOptimizerTest, FirstNodeStaysFixedAndTheRestFollowIt) {
  const PoseGraph truth = SquareLoop();
  PoseGraph graph = truth;
  const Pose2d anchor{0.5, -0.3, 0.4};  // node 0 is off truth: the map frame follows it
  graph.nodes[0].pose = anchor;
  graph.nodes[2].pose = {2.0, 2.0, 0.0};
  ASSERT_TRUE(PoseGraphOptimizer(TightOptions()).Optimize(&graph).usable);
  EXPECT_EQ(graph.nodes[0].pose.x_m, anchor.x_m);
  EXPECT_EQ(graph.nodes[0].pose.y_m, anchor.y_m);
  EXPECT_EQ(graph.nodes[0].pose.yaw_rad, anchor.yaw_rad);
  for (std::size_t i = 1; i < truth.nodes.size(); ++i) {
    ExpectPoseNear(graph.nodes[i].pose, anchor.Compose(truth.nodes[i].pose), 1e-6);
  }
}

// 1-D chain 0 → 1 → 2 along x; odometry says 1 m + 1 m, a loop closure 0 → 2
// says 2.3 m. With no robust loss the optimum is the information-weighted
// average: odometry in series has information w12 = 1 / (1/w1 + 1/w2), so
// x2 = (w12·2 + w3·2.3) / (w12 + w3), and the odometry share of the
// discrepancy splits in proportion to the odometry variances.
TEST(PoseGraphOptimizerTest, InconsistentLoopSettlesAtTheWeightedAverage) {
  const double w1 = 100.0, w2 = 25.0, w3 = 50.0;
  PoseGraph graph = NodesAt({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
  auto info = [](double w) { return Eigen::Vector3d(w, 1e4, 1e4).asDiagonal().toDenseMatrix(); };
  PoseGraphEdge e01 = MakeEdge(graph, 0, 1, EdgeKind::kOdometry, info(w1));
  PoseGraphEdge e12 = MakeEdge(graph, 1, 2, EdgeKind::kOdometry, info(w2));
  PoseGraphEdge e02 = MakeEdge(graph, 0, 2, EdgeKind::kLoopClosure, info(w3));
  e02.measurement.x_m = 2.3;
  graph.edges = {e01, e12, e02};

  PoseGraphOptimizerOptions options = TightOptions();
  options.loop_closure_loss_scale = 0.0;  // plain least squares
  ASSERT_TRUE(PoseGraphOptimizer(options).Optimize(&graph).usable);

  const double w12 = 1.0 / (1.0 / w1 + 1.0 / w2);
  const double x2 = (w12 * 2.0 + w3 * 2.3) / (w12 + w3);
  const double x1 = 1.0 + (x2 - 2.0) * (1.0 / w1) / (1.0 / w1 + 1.0 / w2);
  EXPECT_NEAR(graph.nodes[1].pose.x_m, x1, 1e-7);
  EXPECT_NEAR(graph.nodes[2].pose.x_m, x2, 1e-7);
  for (const PoseGraphNode& node : graph.nodes) {
    EXPECT_NEAR(node.pose.y_m, 0.0, 1e-9);
    EXPECT_NEAR(node.pose.yaw_rad, 0.0, 1e-9);
  }
  // Chi-square of each edge at the optimum, by hand.
  const double x1_m = graph.nodes[1].pose.x_m, x2_m = graph.nodes[2].pose.x_m;
  EXPECT_NEAR(EdgeChiSquare(graph, graph.edges[0]), w1 * std::pow(x1_m - 1.0, 2), 1e-12);
  EXPECT_NEAR(EdgeChiSquare(graph, graph.edges[1]), w2 * std::pow(x2_m - x1_m - 1.0, 2), 1e-12);
  EXPECT_NEAR(EdgeChiSquare(graph, graph.edges[2]), w3 * std::pow(x2_m - 2.3, 2), 1e-12);
}

// A ring of keyframes on a circle, consistent odometry and loop closures
// (σ = 2 cm, 0.01 rad, as scan matching gives), plus one loop closure that is
// wrong by metres.
struct RingGraph {
  PoseGraph truth;
  PoseGraph graph;
  std::size_t bad_edge = 0;
};

RingGraph MakeRingWithBadClosure() {
  RingGraph ring;
  constexpr int kNodes = 40;
  constexpr double kRadiusM = 5.0;
  std::vector<Pose2d> poses;
  for (int i = 0; i < kNodes; ++i) {
    const double t = 2.0 * M_PI * i / kNodes;
    poses.push_back({kRadiusM * std::sin(t), kRadiusM * (1.0 - std::cos(t)), WrapAngle(t)});
  }
  ring.truth = NodesAt(poses);
  const Eigen::Matrix3d info = Eigen::Vector3d(2500.0, 2500.0, 1e4).asDiagonal();
  for (int i = 0; i + 1 < kNodes; ++i) {
    ring.truth.edges.push_back(MakeEdge(ring.truth, i, i + 1, EdgeKind::kOdometry, info));
  }
  for (int i = 0; i < kNodes; i += 8) {  // correct closures across the ring
    ring.truth.edges.push_back(
        MakeEdge(ring.truth, i, (i + kNodes / 2) % kNodes, EdgeKind::kLoopClosure, info));
  }
  ring.truth.edges.push_back(MakeEdge(ring.truth, kNodes - 1, 0, EdgeKind::kLoopClosure, info));
  PoseGraphEdge bad = MakeEdge(ring.truth, 5, 30, EdgeKind::kLoopClosure, info);
  bad.measurement.x_m += 3.0;
  bad.measurement.y_m -= 2.0;
  bad.measurement.yaw_rad = WrapAngle(bad.measurement.yaw_rad + 0.8);
  ring.bad_edge = ring.truth.edges.size();
  ring.truth.edges.push_back(bad);

  ring.graph = ring.truth;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  for (int i = 1; i < kNodes; ++i) {
    Pose2d& pose = ring.graph.nodes[i].pose;
    pose = {pose.x_m + noise(rng), pose.y_m + noise(rng),
            WrapAngle(pose.yaw_rad + 0.3 * noise(rng))};
  }
  return ring;
}

double MaxPositionErrorM(const PoseGraph& graph, const PoseGraph& truth) {
  double worst = 0.0;
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    worst = std::max(worst, std::hypot(graph.nodes[i].pose.x_m - truth.nodes[i].pose.x_m,
                                       graph.nodes[i].pose.y_m - truth.nodes[i].pose.y_m));
  }
  return worst;
}

TEST(PoseGraphOptimizerTest, RobustLossDownweightsAGrosslyWrongLoopClosure) {
  RingGraph robust = MakeRingWithBadClosure();
  PoseGraph plain = robust.graph;

  ASSERT_TRUE(PoseGraphOptimizer(TightOptions()).Optimize(&robust.graph).usable);
  PoseGraphOptimizerOptions no_loss = TightOptions();
  no_loss.loop_closure_loss_scale = 0.0;
  ASSERT_TRUE(PoseGraphOptimizer(no_loss).Optimize(&plain).usable);

  const double robust_error_m = MaxPositionErrorM(robust.graph, robust.truth);
  const double plain_error_m = MaxPositionErrorM(plain, robust.truth);
  EXPECT_LT(robust_error_m, 0.05);
  EXPECT_GT(plain_error_m, 0.3);  // without the loss the bad closure tears the ring

  // The consistency check the front end runs: the bad closure stands out.
  double worst_good = 0.0;
  for (std::size_t i = 0; i < robust.graph.edges.size(); ++i) {
    if (i == robust.bad_edge) continue;
    worst_good = std::max(worst_good, EdgeChiSquare(robust.graph, robust.graph.edges[i]));
  }
  EXPECT_GT(EdgeChiSquare(robust.graph, robust.graph.edges[robust.bad_edge]), 100.0 * worst_good);
}

TEST(PoseGraphOptimizerTest, WarmStartsFromThePosesInTheGraph) {
  RingGraph ring = MakeRingWithBadClosure();
  ring.graph.edges.pop_back();  // drop the bad closure: the truth is the optimum
  const PoseGraphOptimizer optimizer(TightOptions());
  ASSERT_TRUE(optimizer.Optimize(&ring.graph).usable);
  EXPECT_LT(MaxPositionErrorM(ring.graph, ring.truth), 1e-6);
  // Started at the optimum, the solve starts at zero cost and stays there.
  const PoseGraph optimum = ring.graph;
  const OptimizationSummary again = optimizer.Optimize(&ring.graph);
  EXPECT_LT(again.initial_cost, 1e-9);
  EXPECT_LT(MaxPositionErrorM(ring.graph, optimum), 1e-9);
}

TEST(PoseGraphOptimizerTest, TrivialGraphsAreReturnedUnchanged) {
  PoseGraph graph = NodesAt({{1, 2, 3}});
  EXPECT_TRUE(PoseGraphOptimizer({}).Optimize(&graph).usable);
  EXPECT_EQ(graph.nodes[0].pose.x_m, 1.0);
  graph = NodesAt({{1, 2, 3}, {4, 5, 6}});  // two nodes, no edges
  EXPECT_TRUE(PoseGraphOptimizer({}).Optimize(&graph).usable);
  EXPECT_EQ(graph.nodes[1].pose.yaw_rad, 6.0);
}

TEST(PoseGraphOptimizerTest, EdgeChiSquareUsesTheFullInformationMatrix) {
  PoseGraph graph = NodesAt({{0, 0, 0}, {1, 0, 0}});
  PoseGraphEdge edge;
  edge.from_id = 0;
  edge.to_id = 1;
  edge.measurement = {0.9, 0.1, 0.05};
  edge.information << 40.0, 5.0, -2.0, 5.0, 30.0, 3.0, -2.0, 3.0, 80.0;
  const Eigen::Vector3d error(0.1, -0.1, -0.05);
  EXPECT_NEAR(EdgeChiSquare(graph, edge), error.dot(edge.information * error), 1e-12);
  // In the frame of a rotated `from` node the translation error is rotated too.
  graph.nodes[0].pose.yaw_rad = M_PI / 2;
  graph.nodes[1].pose = {0.0, 1.0, M_PI / 2};
  EXPECT_NEAR(EdgeChiSquare(graph, edge), error.dot(edge.information * error), 1e-12);
}

TEST(PoseGraphOptimizerDeathTest, NonPositiveDefiniteInformationAborts) {
  PoseGraph graph = SquareLoop();
  graph.edges[1].information(2, 2) = -1.0;
  EXPECT_DEATH(PoseGraphOptimizer({}).Optimize(&graph), "not positive definite");
  graph = SquareLoop();
  graph.edges[0].to_id = 9;
  EXPECT_DEATH(PoseGraphOptimizer({}).Optimize(&graph), "missing node");
}

}  // namespace
}  // namespace aslam
