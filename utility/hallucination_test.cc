#include "utility/hallucination.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

constexpr double kResolution_m = 0.1;

Point2d Center(int col, int row) {
  return {(col + 0.5) * kResolution_m, (row + 0.5) * kResolution_m};
}

PoseGraph GraphAt(const std::vector<Point2d>& positions_m) {
  PoseGraph graph;
  for (std::size_t i = 0; i < positions_m.size(); ++i) {
    PoseGraphNode node;
    node.id = static_cast<int>(i);
    node.pose = {positions_m[i].x_m, positions_m[i].y_m, 0.0};
    graph.nodes.push_back(node);
  }
  return graph;
}

std::vector<Point2d> StraightPathEast(int num_cells) {
  std::vector<Point2d> path;
  for (int c = 0; c < num_cells; ++c) path.push_back(Center(10 + c, 20));
  return path;
}

void ExpectMatrixNear(const Eigen::Matrix3d& actual, const Eigen::Matrix3d& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-9 * expected.norm()) << actual << "\nvs\n" << expected;
}

TEST(HallucinationTest, OdometryInformationIsHalfInverseSigma) {
  // inv([[0.04, 0.001], [0.001, 0.04]]) = [[0.04, −0.001], [−0.001, 0.04]] / (0.04² − 0.001²).
  const Eigen::Matrix3d info = OdometryInformation({});
  const double det = 0.04 * 0.04 - 0.001 * 0.001;
  EXPECT_NEAR(info(0, 0), 0.5 * 0.04 / det, 1e-9);
  EXPECT_NEAR(info(0, 1), -0.5 * 0.001 / det, 1e-9);
  EXPECT_NEAR(info(1, 1), 0.5 * 0.04 / det, 1e-9);
  EXPECT_NEAR(info(2, 2), 0.5 / 0.008, 1e-9);  // 62.5
  EXPECT_EQ(info(0, 2), 0.0);
}

TEST(HallucinationTest, NodeCountIsCeilPathCellsOver100PlusOne) {
  const OccupancyGrid map(600, 100, kResolution_m, {0.0, 0.0}, OccupancyGrid::kFree);
  const PoseGraph graph = GraphAt({Center(10, 20)});
  // path_cells → ceil(path_cells / 100) + 1 nodes.
  const std::vector<std::pair<int, int>> cases = {{1, 2},   {2, 2},   {100, 2}, {101, 3},
                                                  {200, 3}, {201, 4}, {450, 6}};
  for (const auto& [cells, nodes] : cases) {
    const GraphExtension extension = HallucinatePath(graph, StraightPathEast(cells), map, {});
    EXPECT_EQ(extension.num_new_nodes, nodes) << cells << " path cells";
  }
  EXPECT_EQ(HallucinatePath(graph, {}, map, {}).num_new_nodes, 0);
  EXPECT_EQ(HallucinatePath(PoseGraph{}, StraightPathEast(5), map, {}).num_new_nodes, 0);
}

TEST(HallucinationTest, EvenlySpacedNodesHeadingsAlongPathChainedToNewest) {
  // L-shaped path of 250 cells: east along row 20 over cols 10..159 (indices
  // 0..149), then north along col 159 over rows 21..120 (indices 150..249).
  std::vector<Point2d> path = StraightPathEast(150);
  for (int row = 21; row <= 120; ++row) path.push_back(Center(159, row));
  ASSERT_EQ(path.size(), 250u);
  const OccupancyGrid map(200, 150, kResolution_m, {0.0, 0.0}, OccupancyGrid::kFree);
  const PoseGraph graph = GraphAt({{0.0, 0.0}, {0.5, 0.0}, Center(10, 20)});
  const Hallucination result = HallucinatePathDetailed(graph, path, map, {});

  // K = ceil(250/100) = 3 interior nodes at round(k·249/4) = 62, 125 (124.5), 187; then 249.
  ASSERT_EQ(result.nodes.size(), 4u);
  const int expected_index[] = {62, 125, 187, 249};
  const double expected_yaw[] = {0.0, 0.0, M_PI / 2, M_PI / 2};  // east leg, east, north leg, north
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(result.nodes[k].path_index, expected_index[k]);
    EXPECT_DOUBLE_EQ(result.nodes[k].pose.x_m, path[expected_index[k]].x_m);
    EXPECT_DOUBLE_EQ(result.nodes[k].pose.y_m, path[expected_index[k]].y_m);
    EXPECT_NEAR(result.nodes[k].pose.yaw_rad, expected_yaw[k], 1e-12);
    EXPECT_EQ(result.nodes[k].unknown_fraction, 0.0);  // all free, well inside the map
  }
  // Chain 2 → 3 → 4 → 5 → 6 (newest base node is 2), each I_odo·(1 + 0); no closures.
  ASSERT_EQ(result.edges.size(), 4u);
  ASSERT_EQ(result.extension.num_new_nodes, 4);
  ASSERT_EQ(result.extension.edges.size(), 4u);
  const double odometry_weight = DOptimality(OdometryInformation({}));
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(result.edges[k].from_id, 2 + k);
    EXPECT_EQ(result.edges[k].to_id, 3 + k);
    EXPECT_EQ(result.edges[k].kind, EdgeKind::kOdometry);
    ExpectMatrixNear(result.edges[k].information, OdometryInformation({}));
    EXPECT_EQ(result.extension.edges[k].from, 2 + k);
    EXPECT_EQ(result.extension.edges[k].to, 3 + k);
    EXPECT_NEAR(result.extension.edges[k].weight, odometry_weight, 1e-9);
  }
}

// Hand-drawn map for u and the occupied fraction: 100×100 cells of 0.1 m, free,
// with cols 0..49 unknown and a wall in col `wall_col` of value `wall_value`.
// A new node sits at the centre of cell (50, r). Cells within 1.0 m = 10 cells
// of it are the lattice points dx² + dy² <= 100: 317 of them (Gauss circle,
// r = 10). Unknown: dx < 0, (317 − 21)/2 = 148. Wall at dx = 5: dy² <= 75, |dy| <= 8,
// 17 cells; at dx = 10: only dy = 0, 1 cell.
OccupancyGrid HandDrawnMap(int wall_col, int8_t wall_value) {
  OccupancyGrid map(100, 100, kResolution_m, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 0; row < 100; ++row) {
    for (int col = 0; col < 50; ++col) map.at({col, row}) = OccupancyGrid::kUnknown;
    map.at({wall_col, row}) = wall_value;
  }
  return map;
}

// Path of 3 cells north along col 50 (rows 49..51): ceil(3/100) = 1, so nodes
// at path indices round(2/2) = 1 (cell (50, 50)) and 2 (cell (50, 51)).
std::vector<Point2d> ShortPathNorth() { return {Center(50, 49), Center(50, 50), Center(50, 51)}; }

// 40 base nodes: 0..6 at distances 0.21..1.4 m from both new nodes (on the line
// y = 5.10 between them, so both rank them alike), 7..19 far away, and the 20
// newest (20..39) right next to the new nodes (must never be chosen).
PoseGraph LoopGraph() {
  std::vector<Point2d> positions;
  for (int j = 0; j < 7; ++j) positions.push_back({5.05 - 0.2 * (j + 1), 5.10});
  for (int j = 7; j < 20; ++j) positions.push_back({20.0 + j, 20.0});
  for (int j = 20; j < 40; ++j) positions.push_back({5.05, 5.10});
  return GraphAt(positions);
}

TEST(HallucinationTest, UnknownAndOccupiedFractionsFromHandDrawnMap) {
  const Hallucination result =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 100), {});
  ASSERT_EQ(result.nodes.size(), 2u);
  for (const HallucinatedNode& node : result.nodes) {
    EXPECT_NEAR(node.unknown_fraction, 148.0 / 317.0, 1e-12);
    EXPECT_NEAR(node.occupied_fraction, 17.0 / 317.0, 1e-12);
    EXPECT_NEAR(node.pose.yaw_rad, M_PI / 2, 1e-12);
  }
  // Chain edges carry I_odo·(1 + u).
  ExpectMatrixNear(result.edges.front().information,
                   OdometryInformation({}) * (1.0 + 148.0 / 317.0));
}

TEST(HallucinationTest, CellsOffTheMapCountAsUnknown) {
  // Nodes on the left edge (col 0) of an all-free map: the dx < 0 half is off the grid.
  const OccupancyGrid map(100, 100, kResolution_m, {0.0, 0.0}, OccupancyGrid::kFree);
  const std::vector<Point2d> path = {Center(0, 49), Center(0, 50), Center(0, 51)};
  const Hallucination result = HallucinatePathDetailed(GraphAt({{0.0, 0.0}}), path, map, {});
  ASSERT_EQ(result.nodes.size(), 2u);
  EXPECT_NEAR(result.nodes[0].unknown_fraction, 148.0 / 317.0, 1e-12);
  EXPECT_EQ(result.nodes[0].occupied_fraction, 0.0);
}

TEST(HallucinationTest, LoopClosuresToNearestOldNodesAwayFromNewest) {
  const int n = 40;
  const double occupied = 17.0 / 317.0;  // > 0.03
  const Hallucination result =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 100), {});
  // Per new node: the chain edge, then closures to the 5 nearest of 0..6 (0..4).
  ASSERT_EQ(result.edges.size(), 12u);
  const Eigen::Matrix3d odometry = OdometryInformation({});
  for (int k = 0; k < 2; ++k) {
    const int i = n + k;
    const PoseGraphEdge& chain = result.edges[6 * k];
    EXPECT_EQ(chain.from_id, i - 1);
    EXPECT_EQ(chain.to_id, i);
    for (int c = 0; c < 5; ++c) {
      const PoseGraphEdge& closure = result.edges[6 * k + 1 + c];
      EXPECT_EQ(closure.kind, EdgeKind::kLoopClosure);
      EXPECT_EQ(closure.from_id, i);
      EXPECT_EQ(closure.to_id, c);  // nearest first; never 5, 6 (6th, 7th nearest) nor 20..39
      // I = I_odo·1.5·(|i − j|/N)·occupied fraction.
      ExpectMatrixNear(closure.information, odometry * 1.5 * (i - c) / n * occupied);
      EXPECT_NEAR(result.extension.edges[6 * k + 1 + c].weight, DOptimality(closure.information),
                  1e-12);
    }
  }
  // The extension scores like any other (incremental = from scratch).
  WeightedGraph base{n, {}};
  for (int j = 1; j < n; ++j) base.edges.push_back({j - 1, j, DOptimality(odometry)});
  IncrementalLogDet incremental(base);
  EXPECT_NEAR(incremental.LogDet(result.extension),
              LogDetReducedLaplacianSparse(base, result.extension),
              1e-9 * std::abs(LogDetReducedLaplacianSparse(base, result.extension)));
}

TEST(HallucinationTest, ClosureCountAndExclusionFollowOptions) {
  HallucinationOptions options;
  options.max_loop_closures_per_node = 2;
  options.exclude_newest_nodes = 36;  // only base nodes 0..3 remain eligible
  const Hallucination result =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 100), options);
  std::set<int> targets;
  for (const PoseGraphEdge& edge : result.edges) {
    if (edge.kind == EdgeKind::kLoopClosure) targets.insert(edge.to_id);
  }
  EXPECT_EQ(targets, (std::set<int>{0, 1}));
  options.max_loop_closures_per_node = 5;
  options.loop_closure_radius_m = 0.5;  // 0..1 within 0.5 m (0.21, 0.40); 2 at 0.60
  const Hallucination near =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 100), options);
  EXPECT_EQ(near.edges.size(), 2u + 2u * 2u);
}

TEST(HallucinationTest, NoClosuresWhenOccupiedFractionAtMostThreshold) {
  // Wall at dx = 10: 1/317 ≈ 0.003 <= 0.03.
  const Hallucination thin =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(60, 100), {});
  EXPECT_NEAR(thin.nodes[0].occupied_fraction, 1.0 / 317.0, 1e-12);
  EXPECT_EQ(thin.edges.size(), 2u);  // the chain only
  // A wall of 64 (uncertain, below 65) is not occupied.
  const Hallucination uncertain =
      HallucinatePathDetailed(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 64), {});
  EXPECT_EQ(uncertain.nodes[0].occupied_fraction, 0.0);
  EXPECT_EQ(uncertain.edges.size(), 2u);
  // Threshold raised above 17/317 ≈ 0.054: no closures either.
  HallucinationOptions options;
  options.occupied_fraction_threshold = 0.06;
  EXPECT_EQ(
      HallucinatePath(LoopGraph(), ShortPathNorth(), HandDrawnMap(55, 100), options).edges.size(),
      2u);
}

TEST(HallucinationOptionsTest, ValidationNamesTheField) {
  ValidateHallucinationOptions({});  // defaults are valid
  auto expect_throw_naming = [](HallucinationOptions options, const std::string& field) {
    try {
      ValidateHallucinationOptions(options);
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  HallucinationOptions o;
  o.path_cells_per_node = 0;
  expect_throw_naming(o, "path_cells_per_node");
  o = {};
  o.odometry_sigma_xy = 0.05;  // |Σ_xy| > sqrt(Σ_xx Σ_yy): not positive definite
  expect_throw_naming(o, "odometry_sigma_xy");
  o = {};
  o.odometry_sigma_yawyaw = 0.0;
  expect_throw_naming(o, "odometry_sigma_yawyaw");
  o = {};
  o.loop_closure_radius_m = -1.0;
  expect_throw_naming(o, "loop_closure_radius_m");
  o = {};
  o.occupied_fraction_threshold = 1.5;
  expect_throw_naming(o, "occupied_fraction_threshold");
  o = {};
  o.max_loop_closures_per_node = -1;
  expect_throw_naming(o, "max_loop_closures_per_node");
}

}  // namespace
}  // namespace aslam
