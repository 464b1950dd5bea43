// Hand-made trajectories and grids with known errors.

#include "eval/trajectory_metrics.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

constexpr double kEps = 1e-9;

// Truth in "world": start pose ⊕ a straight run along the start heading at
// 1 m/s, sampled at 50 Hz (every 20 ms) for `duration_us`.
std::vector<TimedPose> StraightTruth(const Pose2d& start, int64_t duration_us) {
  std::vector<TimedPose> truth;
  for (int64_t t = 0; t <= duration_us; t += 20000) {
    truth.push_back({t, start.Compose(Pose2d{t * 1e-6, 0.0, 0.0})});
  }
  return truth;
}

TEST(PoseAt, ExactInterpolatedNearestAndNone) {
  const std::vector<TimedPose> samples = {{1000, {0.0, 0.0, 3.0}}, {2000, {1.0, 2.0, -3.0}}};
  EXPECT_NEAR(PoseAt(samples, 1000, 10)->x_m, 0.0, kEps);
  const Pose2d mid = *PoseAt(samples, 1500, 1000);
  EXPECT_NEAR(mid.x_m, 0.5, kEps);
  EXPECT_NEAR(mid.y_m, 1.0, kEps);
  // Yaw goes the short way through pi: 3.0 -> -3.0 passes 3.0 + 0.1416.
  EXPECT_NEAR(WrapAngle(mid.yaw_rad - (3.0 + (2 * M_PI - 6.0) / 2)), 0.0, kEps);
  // Only one neighbour within the gap: the nearest sample, not an interpolation.
  EXPECT_NEAR(PoseAt(samples, 1900, 200)->x_m, 1.0, kEps);
  EXPECT_NEAR(PoseAt(samples, 900, 200)->x_m, 0.0, kEps);
  EXPECT_NEAR(PoseAt(samples, 2100, 200)->x_m, 1.0, kEps);
  EXPECT_FALSE(PoseAt(samples, 1500, 200));
  EXPECT_FALSE(PoseAt(samples, 2500, 200));
  EXPECT_FALSE(PoseAt({}, 0, 1000000));
}

TEST(ComputeAte, PerfectEstimateFromARotatedStartHasNoError) {
  const Pose2d start{3.0, -2.0, 2.0};
  const auto truth = StraightTruth(start, 5000000);
  std::vector<TimedPose> estimate;  // in "map": the first keyframe is the identity
  for (int64_t t = 0; t <= 5000000; t += 500000) estimate.push_back({t, {t * 1e-6, 0.0, 0.0}});
  const AteResult ate = ComputeAte(estimate, truth);
  EXPECT_EQ(ate.matched, 11);
  EXPECT_EQ(ate.unmatched, 0);
  EXPECT_NEAR(ate.rmse_m, 0.0, kEps);
  EXPECT_NEAR(ate.max_m, 0.0, kEps);
  EXPECT_NEAR(ate.yaw_rmse_rad, 0.0, kEps);
}

TEST(ComputeAte, ConstantOffsetGivesThatOffset) {
  const auto truth = StraightTruth(Pose2d{1.0, 1.0, -0.7}, 4000000);
  std::vector<TimedPose> estimate;
  for (int64_t t = 0; t <= 4000000; t += 400000) estimate.push_back({t, {t * 1e-6, 0.1, 0.05}});
  const AteResult ate = ComputeAte(estimate, truth);
  EXPECT_EQ(ate.matched, 11);
  EXPECT_NEAR(ate.rmse_m, 0.1, kEps);
  EXPECT_NEAR(ate.mean_m, 0.1, kEps);
  EXPECT_NEAR(ate.max_m, 0.1, kEps);
  EXPECT_NEAR(ate.yaw_rmse_rad, 0.05, kEps);
  EXPECT_NEAR(ate.yaw_max_rad, 0.05, kEps);
}

TEST(ComputeAte, KnownErrorsGiveRmseMaxAndWhere) {
  const auto truth = StraightTruth(Pose2d{}, 3000000);
  // Errors 0, 0.3 (x) and 0.4 (y): RMSE sqrt((0.09 + 0.16) / 3), max 0.4 at 2 s.
  const std::vector<TimedPose> estimate = {
      {0, {0.0, 0.0, 0.0}}, {1000000, {1.3, 0.0, 0.0}}, {2000000, {2.0, -0.4, 0.0}}};
  const AteResult ate = ComputeAte(estimate, truth);
  EXPECT_NEAR(ate.rmse_m, std::sqrt(0.25 / 3.0), kEps);
  EXPECT_NEAR(ate.mean_m, 0.7 / 3.0, kEps);
  EXPECT_NEAR(ate.max_m, 0.4, kEps);
  EXPECT_EQ(ate.max_utime, 2000000);
  ASSERT_EQ(ate.errors_m.size(), 3u);
  EXPECT_NEAR(ate.errors_m[1], 0.3, kEps);
}

TEST(ComputeAte, MatchesByUtimeInterpolatingAndSkipsFarEstimates) {
  // Truth runs 0..2 s; estimates between samples are interpolated exactly
  // (straight line), one at 2.5 s has no truth within 100 ms.
  const Pose2d start{0.0, 0.0, 0.5};
  const auto truth = StraightTruth(start, 2000000);
  const std::vector<TimedPose> estimate = {
      {10000, {0.0, 0.0, 0.0}}, {1234567, {1.224567, 0.0, 0.0}}, {2500000, {9.0, 9.0, 0.0}}};
  const AteResult ate = ComputeAte(estimate, truth);
  EXPECT_EQ(ate.matched, 2);
  EXPECT_EQ(ate.unmatched, 1);
  // Anchored at 10 ms (0.01 m along): the estimate 1.224567 m later is exact.
  EXPECT_NEAR(ate.max_m, 0.0, 1e-9);
  // A gap of 12 ms: 10 ms still interpolates (both samples 10 ms away), 1.234567 s
  // has only the sample at 1.24 s within reach and takes it (error 5.433 mm).
  AteOptions narrow;
  narrow.max_time_gap_us = 12000;
  const AteResult nearest = ComputeAte(estimate, truth, narrow);
  EXPECT_EQ(nearest.matched, 2);
  EXPECT_NEAR(nearest.max_m, 0.005433, 1e-9);
}

TEST(ComputeAte, WrapsYawErrors) {
  const std::vector<TimedPose> truth = {{0, {0.0, 0.0, 0.0}}, {1000000, {0.0, 0.0, 3.1}}};
  const std::vector<TimedPose> estimate = {{0, {0.0, 0.0, 0.0}}, {1000000, {0.0, 0.0, -3.1}}};
  const AteResult ate = ComputeAte(estimate, truth);
  EXPECT_NEAR(ate.yaw_max_rad, 2 * M_PI - 6.2, 1e-9);
}

TEST(RelativeTo, MakesOdometryStartAtTheIdentity) {
  const Pose2d anchor{5.0, 1.0, M_PI / 2};
  const auto relative = RelativeTo(anchor, {{0, anchor}, {1, anchor.Compose({1.0, 0.0, 0.0})}});
  EXPECT_NEAR(relative[0].pose.x_m, 0.0, kEps);
  EXPECT_NEAR(relative[1].pose.x_m, 1.0, kEps);
  EXPECT_NEAR(relative[1].pose.y_m, 0.0, kEps);
}

TEST(KeyframePoses, CopiesNodesInOrder) {
  PoseGraph graph;
  graph.nodes = {{0, 100, {}}, {1, 200, {1.0, 0.0, 0.0}}};
  const auto poses = KeyframePoses(graph);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[1].utime, 200);
  EXPECT_EQ(poses[1].pose.x_m, 1.0);
}

// A 40 x 30 truth room at 0.05 m: walls 4 cells thick around a free inside.
OccupancyGrid TruthRoom() {
  OccupancyGrid truth(40, 30, 0.05, {0.0, 0.0}, OccupancyGrid::kOccupied);
  for (int row = 4; row < 26; ++row) {
    for (int col = 4; col < 36; ++col) truth.at({col, row}) = OccupancyGrid::kFree;
  }
  return truth;
}

TEST(ComputeMapAgreement, IdenticalMapAgreesFully) {
  const OccupancyGrid truth = TruthRoom();
  const MapAgreement agreement = ComputeMapAgreement(truth, Pose2d{}, truth);
  EXPECT_EQ(agreement.slam_occupied_cells, 40 * 30 - 32 * 22);
  EXPECT_EQ(agreement.slam_free_cells, 32 * 22);
  EXPECT_DOUBLE_EQ(agreement.occupied_precision, 1.0);
  EXPECT_DOUBLE_EQ(agreement.free_precision, 1.0);
  EXPECT_EQ(agreement.truth_free_cells, 32 * 22);
  EXPECT_DOUBLE_EQ(agreement.coverage, 1.0);
}

TEST(ComputeMapAgreement, CountsKnownWrongCells) {
  const OccupancyGrid truth = TruthRoom();
  OccupancyGrid slam = truth;
  // 5 phantom walls in the middle of the room (far from any wall).
  for (int col = 15; col < 20; ++col) slam.at({col, 15}) = OccupancyGrid::kOccupied;
  // 3 free cells deep inside the wall (0.15 m from the nearest free cell).
  for (int col = 10; col < 13; ++col) slam.at({col, 1}) = OccupancyGrid::kFree;
  // Unknown and in-between values are neither occupied nor free.
  slam.at({8, 8}) = OccupancyGrid::kUnknown;
  slam.at({9, 8}) = 50;
  const MapAgreement a = ComputeMapAgreement(slam, Pose2d{}, truth);
  const int64_t walls = 40 * 30 - 32 * 22 - 3;
  EXPECT_EQ(a.slam_occupied_cells, walls + 5);
  EXPECT_EQ(a.occupied_near_wall, walls);
  EXPECT_EQ(a.slam_free_cells, 32 * 22 - 5 - 2 + 3);
  EXPECT_EQ(a.free_truly_free, 32 * 22 - 5 - 2);
  EXPECT_DOUBLE_EQ(a.occupied_precision, static_cast<double>(walls) / (walls + 5));
  // Coverage counts any known value: only the unknown cell is missing.
  EXPECT_EQ(a.truth_free_known, 32 * 22 - 1);
}

TEST(ComputeMapAgreement, WallToleranceIsCentreToCentre) {
  const OccupancyGrid truth = TruthRoom();
  OccupancyGrid slam(40, 30, 0.05, {0.0, 0.0}, OccupancyGrid::kUnknown);
  slam.at({5, 15}) = OccupancyGrid::kOccupied;  // 2 cells = 0.10 m from the wall at col 3: right
  slam.at({6, 15}) = OccupancyGrid::kOccupied;  // 0.15 m: wrong
  MapAgreement a = ComputeMapAgreement(slam, Pose2d{}, truth);
  EXPECT_EQ(a.slam_occupied_cells, 2);
  EXPECT_EQ(a.occupied_near_wall, 1);
  MapAgreementOptions loose;
  loose.wall_tolerance_m = 0.15;
  EXPECT_EQ(ComputeMapAgreement(slam, Pose2d{}, truth, loose).occupied_near_wall, 2);
  // Free tolerance: a free cell one cell into the wall is right by default, wrong at 0.
  slam.at({3, 15}) = OccupancyGrid::kFree;
  MapAgreementOptions strict;
  strict.free_tolerance_m = 0.0;
  EXPECT_EQ(ComputeMapAgreement(slam, Pose2d{}, truth).free_truly_free, 1);
  EXPECT_EQ(ComputeMapAgreement(slam, Pose2d{}, truth, strict).free_truly_free, 0);
}

TEST(ComputeMapAgreement, PlacesTheSlamMapByTheStartPose) {
  // The SLAM map sees the room from a start at (1.0, 0.5) facing +y: a map
  // point p is the world point start ⊕ p. Sample the truth that way.
  const OccupancyGrid truth = TruthRoom();
  const Pose2d start{1.0, 0.5, M_PI / 2};
  OccupancyGrid slam(30, 40, 0.05, {-0.5, -1.0}, OccupancyGrid::kUnknown);  // covers the room
  for (int row = 0; row < slam.height_cells(); ++row) {
    for (int col = 0; col < slam.width_cells(); ++col) {
      const CellIndex cell = truth.WorldToCell(start.Transform(slam.CellCenter({col, row})));
      slam.at({col, row}) = truth.ValueOr(cell, OccupancyGrid::kUnknown);
    }
  }
  const MapAgreement placed = ComputeMapAgreement(slam, start, truth);
  EXPECT_GT(placed.slam_free_cells, 600);
  EXPECT_DOUBLE_EQ(placed.occupied_precision, 1.0);
  EXPECT_DOUBLE_EQ(placed.free_precision, 1.0);
  EXPECT_DOUBLE_EQ(placed.coverage, 1.0);
  // The same map taken to be at the world origin disagrees.
  const MapAgreement misplaced = ComputeMapAgreement(slam, Pose2d{}, truth);
  EXPECT_LT(misplaced.free_precision, 0.8);
}

TEST(ComputeMapAgreement, CellsOffTheTruthGridAreSolid) {
  const OccupancyGrid truth = TruthRoom();
  OccupancyGrid slam(4, 1, 0.05, {-1.0, -1.0}, OccupancyGrid::kFree);
  slam.at({0, 0}) = OccupancyGrid::kOccupied;
  const MapAgreement a = ComputeMapAgreement(slam, Pose2d{}, truth);
  EXPECT_EQ(a.occupied_near_wall, 1);
  EXPECT_EQ(a.slam_free_cells, 3);
  EXPECT_EQ(a.free_truly_free, 0);
  EXPECT_DOUBLE_EQ(ComputeMapAgreement(OccupancyGrid(), Pose2d{}, truth).coverage, 0.0);
}

// One evaluator over a growing map, as a run uses it: each count is the map's own.
TEST(CoverageEvaluator, FollowsTheMapAsItChangesAndGrows) {
  const OccupancyGrid truth = TruthRoom();  // 32 x 22 free cells from (0.2, 0.2)
  CoverageEvaluator evaluator(truth, Pose2d{});
  // The left half of the room known.
  OccupancyGrid slam(20, 30, 0.05, {0.0, 0.0}, OccupancyGrid::kUnknown);
  for (int row = 4; row < 26; ++row) {
    for (int col = 4; col < 20; ++col) slam.at({col, row}) = OccupancyGrid::kFree;
  }
  EXPECT_EQ(evaluator.Evaluate(slam).truth_free_known, 16 * 22);
  // Same grid, one more column known and one cell unknown again.
  for (int row = 4; row < 26; ++row) slam.at({19, row}) = OccupancyGrid::kFree;
  slam.at({10, 10}) = OccupancyGrid::kUnknown;
  EXPECT_EQ(evaluator.Evaluate(slam).truth_free_known, 16 * 22 - 1);
  // Grown by 20 columns to the right and 10 to the left: the whole room known.
  OccupancyGrid grown(50, 30, 0.05, {-0.5, 0.0}, OccupancyGrid::kOccupied);
  const Coverage all = evaluator.Evaluate(grown);
  EXPECT_EQ(all.truth_free_known, 32 * 22);
  EXPECT_DOUBLE_EQ(all.fraction, 1.0);
  // Back on a grid whose cells lie elsewhere: the room's lower rows are off it.
  OccupancyGrid shifted(40, 10, 0.05, {0.0, 1.0}, OccupancyGrid::kFree);
  EXPECT_EQ(evaluator.Evaluate(shifted).truth_free_known, 32 * 6);
}

// A truth at half the map's cell size puts 4 truth cells in each map cell; a quarter turn
// puts them elsewhere. Each truly free cell counts once, known or not.
TEST(CoverageEvaluator, CountsEveryTruthCellOfAMapCell) {
  OccupancyGrid truth(40, 20, 0.025, {0.0, 0.0}, OccupancyGrid::kFree);  // 1.0 x 0.5 m
  CoverageEvaluator evaluator(truth, Pose2d{});
  OccupancyGrid slam(20, 10, 0.05, {0.0, 0.0}, OccupancyGrid::kUnknown);
  for (int col = 0; col < 5; ++col) slam.at({col, 0}) = OccupancyGrid::kOccupied;
  const Coverage some = evaluator.Evaluate(slam);
  EXPECT_EQ(some.truth_free_cells, 800);
  EXPECT_EQ(some.truth_free_known, 5 * 4);
  slam.at({19, 9}) = OccupancyGrid::kFree;
  EXPECT_EQ(evaluator.Evaluate(slam).truth_free_known, 6 * 4);
  // The map turned by 90 degrees in the world: a truth cell at (x, y) is at (y, -x) in the map.
  CoverageEvaluator turned(truth, Pose2d{0.0, 0.0, M_PI / 2});
  OccupancyGrid upright(10, 20, 0.05, {0.0, -1.0}, OccupancyGrid::kUnknown);
  for (int row = 0; row < 20; ++row) upright.at({0, row}) = OccupancyGrid::kFree;  // y < 0.05 m
  EXPECT_EQ(turned.Evaluate(upright).truth_free_known, 40 * 2);
  EXPECT_EQ(ComputeCoverage(upright, Pose2d{0.0, 0.0, M_PI / 2}, truth).truth_free_known, 40 * 2);
}

}  // namespace
}  // namespace aslam
