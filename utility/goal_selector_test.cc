#include "utility/goal_selector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace aslam {
namespace {

constexpr double kRes = 0.1;                      // m per cell in every test map
constexpr double kHUnknown = 0.4689955935892812;  // h(0.1)
constexpr double kHKnown = 0.9927744539878083;    // h(0.45)

Point2d Center(int col, int row) { return {(col + 0.5) * kRes, (row + 0.5) * kRes}; }

Frontier MakeFrontier(int id, Point2d target_m) {
  Frontier f;
  f.id = id;
  f.target_m = target_m;
  f.centroid_m = target_m;
  f.points_m = {target_m};
  return f;
}

void Fill(OccupancyGrid* map, int col0, int row0, int col1, int row1, int8_t value) {
  for (int r = row0; r <= row1; ++r) {
    for (int c = col0; c <= col1; ++c) map->at({c, r}) = value;
  }
}

// 6 m x 4 m room (60 x 40 cells), free inside a one-cell border wall, with a
// wall at column 20 from the bottom up to row 29 (y < 3.0 m); the gap above
// it (rows 30..38) is the only way from the west part to the east part.
// A box (ring at cols 40..50, rows 5..15) encloses free space.
OccupancyGrid WalledRoom() {
  OccupancyGrid map(60, 40, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  Fill(&map, 0, 0, 59, 0, OccupancyGrid::kOccupied);
  Fill(&map, 0, 39, 59, 39, OccupancyGrid::kOccupied);
  Fill(&map, 0, 0, 0, 39, OccupancyGrid::kOccupied);
  Fill(&map, 59, 0, 59, 39, OccupancyGrid::kOccupied);
  Fill(&map, 20, 0, 20, 29, OccupancyGrid::kOccupied);
  Fill(&map, 40, 5, 50, 5, OccupancyGrid::kOccupied);
  Fill(&map, 40, 15, 50, 15, OccupancyGrid::kOccupied);
  Fill(&map, 40, 5, 40, 15, OccupancyGrid::kOccupied);
  Fill(&map, 50, 5, 50, 15, OccupancyGrid::kOccupied);
  return map;
}

const Pose2d kRoomRobot{1.05, 1.05, 0.0};  // cell (10, 10), west of the wall
// A: just behind the wall, 1.5 m away in a straight line but ~5 m by path (over the gap).
const Point2d kA = Center(25, 10);
// B: straight north, 2.5 m by line and by path (25 cells up column 10).
const Point2d kB = Center(10, 35);
const Point2d kTooClose = Center(11, 11);   // 0.141 m from the robot
const Point2d kInTheBox = Center(45, 10);   // enclosed
const Point2d kAtTheWall = Center(21, 10);  // beside the wall: inscribed, 0.3 m from free space

GoalSelectorOptions Options(UtilityMethod method) {
  GoalSelectorOptions o;
  o.method = method;
  return o;
}

GoalDecision Decide(const GoalSelectorOptions& options, const OccupancyGrid& map, Pose2d robot,
                    const std::vector<Frontier>& frontiers,
                    const std::vector<Point2d>& blacklist = {}, const PoseGraph& graph = {}) {
  GoalSelector selector(options);
  return selector.Decide(map, robot, graph, frontiers, blacklist);
}

TEST(GoalSelectorFd, PicksTheNearestByPathNotByStraightLine) {
  const GoalDecision d = Decide(Options(UtilityMethod::kFd), WalledRoom(), kRoomRobot,
                                {MakeFrontier(1, kA), MakeFrontier(2, kB)});
  ASSERT_EQ(d.scores.size(), 2u);
  const FrontierScore& a = d.scores[0];
  const FrontierScore& b = d.scores[1];
  EXPECT_NEAR(a.distance_m, 1.5, 1e-9);  // A is nearer in a straight line...
  EXPECT_NEAR(b.distance_m, 2.5, 1e-9);
  EXPECT_GT(a.path_length_m, 4.5);          // ...but around the wall it is the farther one
  EXPECT_NEAR(b.path_length_m, 2.5, 1e-5);  // 25 straight steps
  ASSERT_TRUE(d.has_goal());
  EXPECT_EQ(d.chosen().frontier_id, 2);
  EXPECT_TRUE(b.chosen);
  EXPECT_FALSE(a.chosen);
  EXPECT_EQ(d.num_eligible, 2);
  EXPECT_DOUBLE_EQ(b.total, -b.path_length_m);  // fd maximizes -path length
  // fd computes neither U1 nor U2.
  EXPECT_EQ(b.u1, 0.0);
  EXPECT_EQ(b.u2, 0.0);
  EXPECT_EQ(b.ray_cells, 0);
  EXPECT_EQ(d.graph_nodes, 0);
}

TEST(GoalSelectorFd, RespectsTheBlacklistRadius) {
  const std::vector<Frontier> frontiers = {MakeFrontier(1, kA), MakeFrontier(2, kB)};
  // A failed goal 0.3 m from B (radius 0.5): B is out, A (the farther by path) wins.
  GoalDecision d = Decide(Options(UtilityMethod::kFd), WalledRoom(), kRoomRobot, frontiers,
                          {{kB.x_m, kB.y_m - 0.3}});
  EXPECT_EQ(d.scores[1].eligibility, Eligibility::kBlacklisted);
  EXPECT_EQ(d.scores[1].total, -std::numeric_limits<double>::infinity());
  EXPECT_GT(d.scores[1].path_length_m, 0.0);  // still scored, for the record
  ASSERT_TRUE(d.has_goal());
  EXPECT_EQ(d.chosen().frontier_id, 1);

  // 0.6 m away: outside the radius, B wins again.
  d = Decide(Options(UtilityMethod::kFd), WalledRoom(), kRoomRobot, frontiers,
             {{kB.x_m, kB.y_m - 0.6}});
  EXPECT_EQ(d.scores[1].eligibility, Eligibility::kEligible);
  EXPECT_EQ(d.chosen().frontier_id, 2);

  // The radius is the option: 0.7 m covers it.
  GoalSelectorOptions wide = Options(UtilityMethod::kFd);
  wide.blacklist_radius_m = 0.7;
  d = Decide(wide, WalledRoom(), kRoomRobot, frontiers, {{kB.x_m, kB.y_m - 0.6}});
  EXPECT_EQ(d.scores[1].eligibility, Eligibility::kBlacklisted);
  EXPECT_EQ(d.chosen().frontier_id, 1);
}

TEST(GoalSelector, EligibilityReasons) {
  GoalSelectorOptions options = Options(UtilityMethod::kFd);
  options.max_path_length_m = 4.0;  // A (~5 m by path) is too far, B (2.5 m) is not
  options.goal_snap_m = 0.15;
  const GoalDecision d =
      Decide(options, WalledRoom(), kRoomRobot,
             {MakeFrontier(1, kA), MakeFrontier(2, kB), MakeFrontier(3, kTooClose),
              MakeFrontier(4, kInTheBox), MakeFrontier(5, kAtTheWall)});
  EXPECT_EQ(d.scores[0].eligibility, Eligibility::kTooFar);
  EXPECT_EQ(d.scores[1].eligibility, Eligibility::kEligible);
  EXPECT_EQ(d.scores[2].eligibility, Eligibility::kTooClose);
  EXPECT_NEAR(d.scores[2].distance_m, std::sqrt(2.0) * kRes, 1e-12);
  EXPECT_EQ(d.scores[3].eligibility, Eligibility::kUnreachable);
  EXPECT_EQ(d.scores[3].path_length_m, -1.0);
  // Inscribed target, nearest traversable cell 0.3 m away: beyond a snap of 0.15 m.
  EXPECT_EQ(d.scores[4].eligibility, Eligibility::kUnreachable);
  EXPECT_EQ(d.num_eligible, 1);
  EXPECT_EQ(d.chosen().frontier_id, 2);
  for (int i : {0, 2, 3, 4}) {
    EXPECT_EQ(d.scores[i].total, -std::numeric_limits<double>::infinity()) << i;
    EXPECT_FALSE(d.scores[i].chosen) << i;
  }

  // Only frontiers past the limit: the limit does not end exploration, the best of them is chosen.
  const GoalDecision only_far =
      Decide(options, WalledRoom(), kRoomRobot, {MakeFrontier(1, kA), MakeFrontier(3, kTooClose)});
  EXPECT_EQ(only_far.scores[0].eligibility, Eligibility::kEligible);
  EXPECT_EQ(only_far.scores[1].eligibility, Eligibility::kTooClose);
  EXPECT_EQ(only_far.num_eligible, 1);
  ASSERT_TRUE(only_far.has_goal());
  EXPECT_EQ(only_far.chosen().frontier_id, 1);
  EXPECT_EQ(only_far.chosen().total, -only_far.chosen().path_length_m);

  // A snap of 0.35 m reaches the wall target's traversable neighbour (around the wall, like A).
  options.goal_snap_m = 0.35;
  options.max_path_length_m = 0.0;  // no limit
  const GoalDecision snapped =
      Decide(options, WalledRoom(), kRoomRobot, {MakeFrontier(1, kA), MakeFrontier(5, kAtTheWall)});
  EXPECT_EQ(snapped.scores[0].eligibility, Eligibility::kEligible);
  EXPECT_EQ(snapped.scores[1].eligibility, Eligibility::kEligible);
  EXPECT_NEAR(snapped.scores[1].path_length_m, snapped.scores[0].path_length_m, 0.5);

  // Nothing eligible: no goal, every total -inf.
  const GoalDecision none = Decide(Options(UtilityMethod::kFd), WalledRoom(), kRoomRobot,
                                   {MakeFrontier(3, kTooClose), MakeFrontier(4, kInTheBox)});
  EXPECT_FALSE(none.has_goal());
  EXPECT_EQ(none.chosen_index, -1);
  EXPECT_EQ(none.num_eligible, 0);
  // No frontiers at all: no goal either.
  EXPECT_FALSE(Decide(Options(UtilityMethod::kFd), WalledRoom(), kRoomRobot, {}).has_goal());
}

TEST(GoalSelector, CanReachAsDecideDoes) {
  GoalSelectorOptions options = Options(UtilityMethod::kOurs);
  options.goal_snap_m = 0.15;
  GoalSelector selector(options);
  const OccupancyGrid room = WalledRoom();
  EXPECT_TRUE(selector.CanReach(room, kRoomRobot, kA));  // around the wall
  EXPECT_TRUE(selector.CanReach(room, kRoomRobot, kB));
  EXPECT_FALSE(selector.CanReach(room, kRoomRobot, kInTheBox));
  EXPECT_FALSE(selector.CanReach(room, kRoomRobot, kAtTheWall));  // snap too short
  // The gap over the wall shut: A is cut off, B is not.
  OccupancyGrid shut = room;
  Fill(&shut, 20, 30, 20, 38, OccupancyGrid::kOccupied);
  EXPECT_FALSE(selector.CanReach(shut, kRoomRobot, kA));
  EXPECT_TRUE(selector.CanReach(shut, kRoomRobot, kB));
  // A snap long enough reaches the wall target's traversable neighbour.
  options.goal_snap_m = 0.35;
  EXPECT_TRUE(GoalSelector(options).CanReach(room, kRoomRobot, kAtTheWall));
}

TEST(GoalSelector, RobotOffTheMapReachesNothing) {
  const GoalDecision d =
      Decide(Options(UtilityMethod::kFd), WalledRoom(), {-3.0, -3.0, 0.0}, {MakeFrontier(2, kB)});
  EXPECT_EQ(d.scores[0].eligibility, Eligibility::kUnreachable);
  EXPECT_FALSE(d.has_goal());
}

// A single-node graph in an all-free 4 m x 4 m map; robot at cell (5, 20), the
// only graph node there too, frontier target at cell (15, 20), 1.0 m east.
//   Path: 10 straight steps, 11 cells, length 1.0 m.
//   Hallucination: ceil(11/100) = 1 node at path index round(10/2) = 5 plus one
//   at the target; every cell within 1 m of them is free: u = 0, no closures
//   (the base has fewer than 21 nodes). Two chain edges of weight
//   D = D-opt(I_odo) = det(½ Σ_odo⁻¹)^(1/3) = (0.125 / 1.2792e-5)^(1/3) = 21.379154252164916.
//   Extended graph: a path of 3 nodes; L̃ (node 0 removed) = [[2D, -D], [-D, D]],
//   det = D², n_v = 3: U1 = 3^(1/3) · (D²)^(1/3) = 11.10965993383994.
//   U2: ray of 11 known cells, E/K = h(0.45) = 0.9927744539878083; d = 1.0 m,
//   γ = exp(-0.6) = 0.5488116360940264; β = 2 (U1 = 11.1), ρ = 100;
//   U2 = (1 - 0.9927744539878083) · 100 + 0.5488116360940264 = 1.2713662373131984.
//   total (ours) = 11.10965993383994 + 1.2713662373131984 = 12.381026171153138.
TEST(GoalSelectorOurs, TotalOnATinyGraphWorkedByHand) {
  const OccupancyGrid map(40, 40, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  PoseGraph graph;
  graph.nodes.push_back({0, 0, {0.55, 2.05, 0.0}});
  const Pose2d robot{0.55, 2.05, 0.0};
  const std::vector<Frontier> frontiers = {MakeFrontier(7, Center(15, 20))};

  const GoalDecision ours = Decide(Options(UtilityMethod::kOurs), map, robot, frontiers, {}, graph);
  ASSERT_TRUE(ours.has_goal());
  const FrontierScore& s = ours.scores[0];
  EXPECT_EQ(ours.graph_nodes, 1);
  EXPECT_NEAR(s.path_length_m, 1.0, 1e-6);
  EXPECT_EQ(s.hallucinated_nodes, 2);
  EXPECT_EQ(s.hallucinated_edges, 2);
  EXPECT_NEAR(s.u1, 11.10965993383994, 1e-9);
  EXPECT_EQ(s.ray_cells, 11);
  EXPECT_NEAR(s.mean_entropy_bits, kHKnown, 1e-12);
  EXPECT_NEAR(s.gamma, 0.5488116360940264, 1e-12);
  EXPECT_EQ(s.beta, 2);
  EXPECT_DOUBLE_EQ(s.rho, 100.0);
  EXPECT_NEAR(s.u2, 1.2713662373131984, 1e-9);
  EXPECT_NEAR(s.total, 12.381026171153138, 1e-9);

  // ags: the same U1 is the total; U2 terms stay 0.
  const GoalDecision ags = Decide(Options(UtilityMethod::kAgs), map, robot, frontiers, {}, graph);
  EXPECT_NEAR(ags.scores[0].total, 11.10965993383994, 1e-9);
  EXPECT_EQ(ags.scores[0].u2, 0.0);
  EXPECT_EQ(ags.scores[0].rho, 0.0);
}

TEST(GoalSelectorOurs, EmptyOrBrokenGraphLeavesU1AtZeroAndSaysSo) {
  const OccupancyGrid map(40, 40, kRes, {0.0, 0.0}, OccupancyGrid::kFree);
  const Pose2d robot{0.55, 2.05, 0.0};
  const std::vector<Frontier> frontiers = {MakeFrontier(7, Center(15, 20))};
  GoalDecision d = Decide(Options(UtilityMethod::kAgs), map, robot, frontiers, {}, PoseGraph{});
  EXPECT_EQ(d.scores[0].u1, 0.0);
  EXPECT_NE(d.note.find("empty"), std::string::npos);

  PoseGraph split;  // two nodes, no edge
  split.nodes.push_back({0, 0, {0.55, 2.05, 0.0}});
  split.nodes.push_back({1, 0, {0.65, 2.05, 0.0}});
  d = Decide(Options(UtilityMethod::kAgs), map, robot, frontiers, {}, split);
  EXPECT_EQ(d.scores[0].u1, 0.0);
  EXPECT_NE(d.note.find("not connected"), std::string::npos);
  EXPECT_TRUE(d.has_goal());  // still a goal: the ranking degrades, the robot keeps exploring
}

// An 8.1 m x 4 m corridor, mirror-symmetric about the robot's column 40
// (x = 4.05 m): solid walls below row 12 and above row 27, free inside,
// unknown at both ends (columns 0..9 and 71..80). Frontier A at column 15
// (2.5 m west), B at column 65 (2.5 m east), both on the robot's row 20.
OccupancyGrid Corridor() {
  OccupancyGrid map(81, 40, kRes, {0.0, 0.0}, OccupancyGrid::kOccupied);
  Fill(&map, 0, 12, 80, 27, OccupancyGrid::kFree);
  Fill(&map, 0, 12, 9, 27, OccupancyGrid::kUnknown);
  Fill(&map, 71, 12, 80, 27, OccupancyGrid::kUnknown);
  return map;
}
const Pose2d kCorridorRobot{4.05, 2.05, 0.0};
const Point2d kWest = Center(15, 20);
const Point2d kEast = Center(65, 20);

// A chain of odometry edges with a fixed information matrix.
PoseGraph Chain(const std::vector<Point2d>& positions) {
  PoseGraph graph;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    graph.nodes.push_back({static_cast<int>(i), 0, {positions[i].x_m, positions[i].y_m, 0.0}});
    if (i > 0) {
      PoseGraphEdge e;
      e.from_id = static_cast<int>(i) - 1;
      e.to_id = static_cast<int>(i);
      e.information = Eigen::Vector3d(400.0, 400.0, 1000.0).asDiagonal();
      graph.edges.push_back(e);
    }
  }
  return graph;
}

TEST(GoalSelectorAgs, PathPastOldNodesInClutterGetsClosuresAndAHigherU1) {
  // 30 nodes: 0..9 old ones at x = 1.5..2.4 m (west), 10..29 the newest 20 from
  // x = 2.5 m to the robot. Every hallucinated node lies 0.8-0.9 m from both
  // walls (occupied fraction within 1 m ≈ 7 % > 3 %). A's nodes (x = 2.75 and
  // 1.55 m) have old nodes within 2 m: hallucinated loop closures. B's (x = 5.35
  // and 6.55 m) have only the excluded newest 20 within 2 m: a bare chain. All
  // else is mirror-symmetric, and extra edges only add spanning trees, so
  // U1(A) > U1(B): ags and ours both pick A.
  std::vector<Point2d> positions;
  for (int k = 0; k < 10; ++k) positions.push_back({1.5 + 0.1 * k, 2.05});
  for (int k = 0; k < 20; ++k) positions.push_back({2.5 + k * (1.55 / 19.0), 2.05});
  const PoseGraph graph = Chain(positions);
  const OccupancyGrid map = Corridor();
  const std::vector<Frontier> frontiers = {MakeFrontier(1, kWest), MakeFrontier(2, kEast)};

  const GoalDecision ags =
      Decide(Options(UtilityMethod::kAgs), map, kCorridorRobot, frontiers, {}, graph);
  const FrontierScore& a = ags.scores[0];
  const FrontierScore& b = ags.scores[1];
  EXPECT_EQ(ags.graph_nodes, 30);
  EXPECT_NEAR(a.path_length_m, b.path_length_m, 1e-5);  // 25 straight steps each way
  EXPECT_EQ(a.hallucinated_nodes, 2);
  EXPECT_EQ(b.hallucinated_nodes, 2);
  EXPECT_EQ(b.hallucinated_edges, 2);  // the chain only
  EXPECT_GT(a.hallucinated_edges, 2);  // plus closures to the old nodes
  EXPECT_GT(a.u1, b.u1);
  ASSERT_TRUE(ags.has_goal());
  EXPECT_EQ(ags.chosen().frontier_id, 1);

  // Each U1 equals the from-scratch value for the same path (dense log det).
  const Costmap costmap(map, CostmapOptions{});
  const GlobalPlanner planner;
  const WeightedGraph base = ToWeightedGraph(graph);
  for (const FrontierScore* s : {&a, &b}) {
    const auto path = planner.Plan(costmap, {kCorridorRobot.x_m, kCorridorRobot.y_m}, s->target_m);
    ASSERT_TRUE(path.has_value());
    const GraphExtension ext = HallucinatePath(graph, path->points_m, map, HallucinationOptions{});
    const double u1 =
        U1FromLogDet(LogDetReducedLaplacianDense(base, ext), base.num_nodes + ext.num_new_nodes);
    EXPECT_NEAR(s->u1, u1, 1e-9 * u1) << s->frontier_id;
  }

  const GoalDecision ours =
      Decide(Options(UtilityMethod::kOurs), map, kCorridorRobot, frontiers, {}, graph);
  ASSERT_TRUE(ours.has_goal());
  EXPECT_EQ(ours.chosen().frontier_id, 1);
  EXPECT_NEAR(ours.scores[0].u1, a.u1, 1e-9 * a.u1);
  // Mirror images: the same ray mix and distance.
  EXPECT_EQ(ours.scores[0].ray_cells, ours.scores[1].ray_cells);
  EXPECT_NEAR(ours.scores[0].mean_entropy_bits, ours.scores[1].mean_entropy_bits, 1e-12);
  for (const FrontierScore& s : ours.scores) EXPECT_DOUBLE_EQ(s.total, s.u1 + s.u2);
}

// The corridor with two unknown cells on the ray to kWest (columns 38, 39), and a 10-node
// graph near the robot whose newest nodes leave no closure candidates.
OccupancyGrid CorridorWithUnknownOnARay() {
  OccupancyGrid map = Corridor();
  map.at({38, 20}) = OccupancyGrid::kUnknown;
  map.at({39, 20}) = OccupancyGrid::kUnknown;
  return map;
}
PoseGraph GraphNearTheCorridorRobot() {
  std::vector<Point2d> positions;
  for (int k = 0; k < 10; ++k) positions.push_back({3.15 + 0.1 * k, 2.05});
  return Chain(positions);
}

TEST(GoalSelectorOurs, PathEntropyDecidesWhereU1Ties) {
  // The corridor with a 10-node graph near the robot (no closure candidates:
  // all among the newest 20), so A and B hallucinate mirror-image chains and
  // U1(A) = U1(B). Two unknown cells on A's ray at columns 38, 39 (1.1-1.2 m
  // from A's nearest hallucinated node at column 27, so outside its 1 m
  // counts) make A's ray the less known one:
  //   E_A/K = (24 h(0.45) + 2 h(0.1)) / 26, E_B/K = h(0.45)
  //   U2(A) - U2(B) = ρ · 2 (h(0.45) - h(0.1)) / 26 = ρ · 0.04029068156911746
  // The planner skirts the two cells diagonally (3.83 < 4.19 in cost), so A's
  // path is ~0.08 m longer: ags, seeing a tie, takes the shorter B; ours takes A.
  const OccupancyGrid map = CorridorWithUnknownOnARay();
  const PoseGraph graph = GraphNearTheCorridorRobot();
  const std::vector<Frontier> frontiers = {MakeFrontier(1, kWest), MakeFrontier(2, kEast)};

  const GoalDecision ags =
      Decide(Options(UtilityMethod::kAgs), map, kCorridorRobot, frontiers, {}, graph);
  EXPECT_NEAR(ags.scores[0].u1, ags.scores[1].u1, 1e-12 * ags.scores[1].u1);
  EXPECT_GT(ags.scores[0].path_length_m, ags.scores[1].path_length_m);
  ASSERT_TRUE(ags.has_goal());
  EXPECT_EQ(ags.chosen().frontier_id, 2);

  const GoalDecision ours =
      Decide(Options(UtilityMethod::kOurs), map, kCorridorRobot, frontiers, {}, graph);
  const FrontierScore& a = ours.scores[0];
  const FrontierScore& b = ours.scores[1];
  EXPECT_EQ(a.ray_cells, 26);
  EXPECT_NEAR(a.path_entropy_bits, 24 * kHKnown + 2 * kHUnknown, 1e-12);
  EXPECT_NEAR(b.path_entropy_bits, 26 * kHKnown, 1e-12);
  EXPECT_EQ(a.rho, b.rho);
  EXPECT_NEAR(a.u2 - b.u2, a.rho * 0.04029068156911746, 1e-9 * a.rho);
  ASSERT_TRUE(ours.has_goal());
  EXPECT_EQ(ours.chosen().frontier_id, 1);
}

// The corridor of PathEntropyDecidesWhereU1Ties, where ours takes A (west) over B (east),
// with frontiers of cells that border the unknown ends. Each end shut off from the map's
// edge makes it an enclosed pocket of under 1.6 m^2.
TEST(GoalSelectorOurs, PocketsWaitUntilNothingElseIsLeftThenGoNearestFirst) {
  OccupancyGrid map = CorridorWithUnknownOnARay();
  const PoseGraph graph = GraphNearTheCorridorRobot();
  auto frontier_along = [](int id, int col, Point2d target_m) {
    Frontier f = MakeFrontier(id, target_m);
    f.points_m.clear();
    for (int row = 13; row <= 26; ++row) f.points_m.push_back(Center(col, row));
    return f;
  };
  const std::vector<Frontier> frontiers = {frontier_along(1, 10, kWest),
                                           frontier_along(2, 70, kEast)};
  GoalSelectorOptions options = Options(UtilityMethod::kOurs);
  const GoalDecision off = Decide(options, map, kCorridorRobot, frontiers, {}, graph);
  ASSERT_TRUE(off.has_goal());
  EXPECT_EQ(off.chosen().frontier_id, 1);
  EXPECT_FALSE(off.scores[0].pocket);
  EXPECT_EQ(off.scores[0].bordered_unknown_m2, 0.0);  // not measured while off

  // The west end shut: a pocket, left while the open east end is eligible.
  options.pocket_max_area_m2 = 4.0;
  Fill(&map, 0, 12, 0, 27, OccupancyGrid::kOccupied);
  const GoalDecision west_shut = Decide(options, map, kCorridorRobot, frontiers, {}, graph);
  const FrontierScore& west = west_shut.scores[0];
  EXPECT_TRUE(west.pocket);
  EXPECT_GT(west.bordered_unknown_m2, 0.0);
  EXPECT_LT(west.bordered_unknown_m2, 1.6);
  EXPECT_EQ(west.eligibility, Eligibility::kPocket);
  EXPECT_EQ(west.total, -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isinf(west_shut.scores[1].bordered_unknown_m2));
  EXPECT_FALSE(west_shut.scores[1].pocket);
  ASSERT_TRUE(west_shut.has_goal());
  EXPECT_EQ(west_shut.chosen().frontier_id, 2);
  EXPECT_EQ(west_shut.num_eligible, 1);
  // Planning only through known cells measures the same pockets.
  GoalSelectorOptions known_only = options;
  known_only.costmap.unknown_passable = false;
  const GoalDecision known = Decide(known_only, map, kCorridorRobot, frontiers, {}, graph);
  EXPECT_EQ(known.scores[0].bordered_unknown_m2, west.bordered_unknown_m2);
  EXPECT_TRUE(std::isinf(known.scores[1].bordered_unknown_m2));

  // Only the east end (B) shut: a pocket within pocket_near_m by path is chosen at once over
  // the open west end that U1 + U2 takes; one just beyond it still waits.
  OccupancyGrid east_shut_map = CorridorWithUnknownOnARay();
  Fill(&east_shut_map, 80, 12, 80, 27, OccupancyGrid::kOccupied);
  GoalSelectorOptions near = options;
  const GoalDecision east_waits = Decide(near, east_shut_map, kCorridorRobot, frontiers, {}, graph);
  ASSERT_TRUE(east_waits.has_goal());
  EXPECT_EQ(east_waits.chosen().frontier_id, 1);
  const FrontierScore& east = east_waits.scores[1];
  ASSERT_TRUE(east.pocket);
  near.pocket_near_m = east.path_length_m;
  const GoalDecision cleared = Decide(near, east_shut_map, kCorridorRobot, frontiers, {}, graph);
  ASSERT_TRUE(cleared.has_goal());
  EXPECT_EQ(cleared.chosen().frontier_id, 2);
  EXPECT_EQ(cleared.num_eligible, 2);
  EXPECT_DOUBLE_EQ(cleared.chosen().total, -east.path_length_m);
  EXPECT_FALSE(cleared.scores[0].chosen);
  near.pocket_near_m = east.path_length_m - 0.01;
  EXPECT_EQ(Decide(near, east_shut_map, kCorridorRobot, frontiers, {}, graph).chosen().frontier_id,
            1);

  // Both ends shut: only pockets, chosen from nearest first (B's path is the shorter),
  // not by U1 + U2 (which prefers A).
  Fill(&map, 80, 12, 80, 27, OccupancyGrid::kOccupied);
  const GoalDecision both_shut = Decide(options, map, kCorridorRobot, frontiers, {}, graph);
  ASSERT_TRUE(both_shut.has_goal());
  EXPECT_EQ(both_shut.num_eligible, 2);
  EXPECT_EQ(both_shut.chosen().frontier_id, 2);
  EXPECT_TRUE(both_shut.chosen().pocket);
  EXPECT_LT(both_shut.scores[1].path_length_m, both_shut.scores[0].path_length_m);
  for (const FrontierScore& s : both_shut.scores) {
    EXPECT_EQ(s.eligibility, Eligibility::kEligible);
    EXPECT_DOUBLE_EQ(s.total, -s.path_length_m);
  }
  // The same map with pockets off: ours' own score still takes A.
  options.pocket_max_area_m2 = 0.0;
  EXPECT_EQ(Decide(options, map, kCorridorRobot, frontiers, {}, graph).chosen().frontier_id, 1);
}

TEST(GoalSelector, IsConnected) {
  WeightedGraph g;
  g.num_nodes = 3;
  g.edges = {{0, 1, 1.0}};
  EXPECT_FALSE(IsConnected(g));
  g.edges.push_back({2, 1, 0.0});  // carries no information
  EXPECT_FALSE(IsConnected(g));
  g.edges.push_back({2, 0, 0.5});
  EXPECT_TRUE(IsConnected(g));
  EXPECT_TRUE(IsConnected(WeightedGraph{1, {}}));
  EXPECT_FALSE(IsConnected(WeightedGraph{0, {}}));
}

TEST(GoalSelector, MethodNamesAndBadOptions) {
  for (UtilityMethod m : {UtilityMethod::kFd, UtilityMethod::kAgs, UtilityMethod::kOurs}) {
    EXPECT_EQ(ParseUtilityMethod(UtilityMethodName(m)), m);
  }
  EXPECT_FALSE(ParseUtilityMethod("best").has_value());
  GoalSelectorOptions bad;
  bad.blacklist_radius_m = -1.0;
  EXPECT_THROW(GoalSelector{bad}, std::invalid_argument);
  auto expect_rejected_naming = [](const GoalSelectorOptions& options, const std::string& field) {
    try {
      GoalSelector{options};
      ADD_FAILURE() << "a negative " << field << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  GoalSelectorOptions bad_pocket;
  bad_pocket.pocket_max_area_m2 = -0.5;
  expect_rejected_naming(bad_pocket, "pocket_max_area_m2");
  GoalSelectorOptions bad_near;
  bad_near.pocket_near_m = -1.0;
  expect_rejected_naming(bad_near, "pocket_near_m");
}

TEST(GoalSelectorTest, PointsToRetryForgiveOnlyWhatBlocksABlacklistedFrontierOnce) {
  GoalSelector selector{GoalSelectorOptions{}};  // blacklist radius 0.5 m
  GoalDecision decision;
  FrontierScore blocked, reachable, unreachable;
  blocked.target_m = {2.0, 0.0};
  blocked.eligibility = Eligibility::kBlacklisted;
  reachable.target_m = {5.0, 0.0};  // eligible: nothing to forgive for it
  unreachable.target_m = {8.0, 0.0};
  unreachable.eligibility = Eligibility::kUnreachable;
  decision.scores = {blocked, reachable, unreachable};
  const std::vector<Point2d> blacklist = {
      {2.3, 0.0}, {5.2, 0.0}, {2.0, 0.4}, {8.0, 0.0}, {9.0, 0.0}};
  EXPECT_EQ(selector.PointsToRetry(decision, blacklist, {}), (std::vector<std::size_t>{0, 2}));
  // Once one of its points was forgiven before, the frontier is not retried again.
  EXPECT_TRUE(selector.PointsToRetry(decision, blacklist, {{2.1, 0.1}}).empty());
  EXPECT_EQ(selector.PointsToRetry(decision, blacklist, {{9.0, 0.0}}),
            (std::vector<std::size_t>{0, 2}));
}

}  // namespace
}  // namespace aslam
