#include "slam/scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>

#include "drivers/sim/lidar.h"
#include "drivers/sim/sim_world.h"

namespace aslam {
namespace {

constexpr double kResolution_m = 0.05;

// Marks the cells of [x0, x1] x [y0, y1] on the grid solid.
void FillRect(OccupancyGrid* grid, double x0, double y0, double x1, double y1) {
  const CellIndex lo = grid->WorldToCell({x0, y0});
  const CellIndex hi = grid->WorldToCell({x1, y1});
  for (int row = std::max(lo.row, 0); row <= std::min(hi.row, grid->height_cells() - 1); ++row) {
    for (int col = std::max(lo.col, 0); col <= std::min(hi.col, grid->width_cells() - 1); ++col) {
      grid->at({col, row}) = OccupancyGrid::kOccupied;
    }
  }
}

// A free rectangle [1, 1 + width] x [1, 1 + height] walled in, in a 1 m margin.
OccupancyGrid WalledRoom(double width_m, double height_m) {
  OccupancyGrid grid(static_cast<int>(std::lround((width_m + 2.0) / kResolution_m)),
                     static_cast<int>(std::lround((height_m + 2.0) / kResolution_m)), kResolution_m,
                     {0.0, 0.0}, OccupancyGrid::kFree);
  FillRect(&grid, 0.0, 0.0, width_m + 2.0, 0.99);
  FillRect(&grid, 0.0, height_m + 1.01, width_m + 2.0, height_m + 2.0);
  FillRect(&grid, 0.0, 0.0, 0.99, height_m + 2.0);
  FillRect(&grid, width_m + 1.01, 0.0, width_m + 2.0, height_m + 2.0);
  return grid;
}

// A 10 m x 8 m room with furniture, so no pose is ambiguous.
OccupancyGrid FurnishedRoom() {
  OccupancyGrid grid = WalledRoom(10.0, 8.0);
  FillRect(&grid, 2.0, 2.0, 2.8, 2.6);
  FillRect(&grid, 8.0, 5.0, 8.5, 6.5);
  FillRect(&grid, 5.0, 7.0, 5.2, 9.0);   // a partition from the top wall
  FillRect(&grid, 9.0, 1.0, 11.0, 2.2);  // a cupboard in a corner
  return grid;
}

class Scanner {
 public:
  explicit Scanner(const OccupancyGrid& grid) : world_(grid), lidar_(LidarOptions{}), rng_(7) {}
  std::shared_ptr<const PointCloud2d> Points(const Pose2d& pose, double spacing_m = 0.05) {
    return std::make_shared<const PointCloud2d>(
        ScanToPoints(lidar_.Scan(world_, pose, 0, 0, rng_), spacing_m));
  }

 private:
  SimWorld world_;
  LidarModel lidar_;
  std::mt19937_64 rng_;
};

CorrelationMap MapFrom(Scanner* scanner, const std::vector<Pose2d>& keyframes,
                       const ScanMatcherOptions& options) {
  std::vector<PosedPoints> scans;
  for (const Pose2d& pose : keyframes) scans.push_back({pose, scanner->Points(pose)});
  return CorrelationMap(scans, options);
}

TEST(ScanToPointsTest, SkipsInvalidReturnsAndAppliesSensorPose) {
  LidarScan scan;
  scan.sensor_pose = {0.2, 0.1, M_PI / 2};
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = M_PI / 2;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  scan.range_m = {1.0f, nan, inf, 0.0f, -1.0f, 11.0f, 0.05f, 2.0f};
  const PointCloud2d points = ScanToPoints(scan, 0.0);
  ASSERT_EQ(points.size(), 2u);
  // Beam 0 (angle 0) along the sensor's x, which is the base's y.
  EXPECT_NEAR(points[0].x_m, 0.2, 1e-6);
  EXPECT_NEAR(points[0].y_m, 1.1, 1e-6);
  // Beam 7: angle 7 pi/2 = -pi/2 in the sensor, +x in the base.
  EXPECT_NEAR(points[1].x_m, 2.2, 1e-6);
  EXPECT_NEAR(points[1].y_m, 0.1, 1e-6);

  // Limits that let 0 and inf through IsValidReturn must not yield points.
  scan.range_min_m = 0.0;
  scan.range_max_m = inf;
  EXPECT_EQ(ScanToPoints(scan, 0.0).size(), 4u);  // 1, 11, 0.05, 2
}

TEST(ScanToPointsTest, ThinsToSpacing) {
  LidarScan scan;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2 * M_PI / 720;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.range_m.assign(720, 2.0f);  // a circle of 4 pi m, points 1.75 cm apart
  EXPECT_EQ(ScanToPoints(scan, 0.0).size(), 720u);
  const PointCloud2d points = ScanToPoints(scan, 0.1);
  ASSERT_GT(points.size(), 1u);
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_GE(std::hypot(points[i].x_m - points[i - 1].x_m, points[i].y_m - points[i - 1].y_m),
              0.1 - 1e-9);
  }
  // Every 6th beam is kept (6 * 1.745 cm >= 10 cm > 5 * 1.745 cm).
  EXPECT_EQ(points.size(), 120u);
}

TEST(CorrelationMapTest, LikelihoodIsSmearedAroundMapPoints) {
  ScanMatcherOptions options;
  const auto points = std::make_shared<const PointCloud2d>(PointCloud2d{{1.0, 0.0}});
  const CorrelationMap map({{{0.0, 1.0, M_PI / 2}, points}}, options);  // the point at (0, 2)
  ASSERT_FALSE(map.empty());
  EXPECT_NEAR(map.Likelihood({0.01, 2.01}), 1.0, 1e-6);
  // One cell (one sigma) away.
  EXPECT_NEAR(map.Likelihood({0.06, 2.01}), std::exp(-0.5), 2e-3);  // stored in 1/255
  EXPECT_EQ(map.Likelihood({0.5, 2.0}), 0.0);
  EXPECT_EQ(map.Likelihood({100.0, 2.0}), 0.0);
}

TEST(ScanMatcherOptionsTest, ValidationNamesTheBadField) {
  EXPECT_NO_THROW(ValidateScanMatcherOptions(ScanMatcherOptions{}));
  ScanMatcherOptions options;
  options.smear_sigma_m = 0.0;
  try {
    ValidateScanMatcherOptions(options);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("smear_sigma_m"), std::string::npos) << error.what();
  }
  options = {};
  options.coarse_factor = 1;
  EXPECT_THROW(ValidateScanMatcherOptions(options), std::invalid_argument);
}

TEST(ScanMatcherTest, EmptyMapOrScanIsNotFound) {
  ScanMatcherOptions options;
  const ScanMatcher matcher(options);
  const auto some_points =
      std::make_shared<const PointCloud2d>(PointCloud2d{{1.0, 0.0}, {0.0, 1.0}});
  const CorrelationMap empty_map({}, options);
  EXPECT_TRUE(empty_map.empty());
  EXPECT_FALSE(matcher.Match(empty_map, *some_points, {}, {}).found);
  const CorrelationMap no_points_map({{{}, std::make_shared<const PointCloud2d>()}, {{}, nullptr}},
                                     options);
  EXPECT_TRUE(no_points_map.empty());

  const CorrelationMap map({{{}, some_points}}, options);
  ASSERT_FALSE(map.empty());
  EXPECT_FALSE(matcher.Match(map, {}, {}, {}).found);
  // Only points beyond max_point_range_m: nothing to match.
  EXPECT_FALSE(matcher.Match(map, {{50.0, 0.0}}, {}, {}).found);
  // Nothing overlaps the map anywhere in the window.
  EXPECT_FALSE(matcher.Match(map, {{1.0, 0.0}}, {5.0, 5.0, 0.0}, {}).found);
  EXPECT_TRUE(matcher.Match(map, *some_points, {}, {}).found);
}

TEST(ScanMatcherTest, RecoversKnownOffsets) {
  Scanner scanner(FurnishedRoom());
  ScanMatcherOptions options;
  const CorrelationMap map =
      MapFrom(&scanner, {{4.0, 3.0, 0.0}, {4.3, 3.2, 0.2}, {4.6, 3.0, -0.1}}, options);
  const ScanMatcher matcher(options);
  const Pose2d truth{4.8, 3.4, 0.15};
  const auto points = scanner.Points(truth);
  // (dx, dy, dyaw) of the truth from the prediction; the last ones near the edge.
  const Pose2d offsets[] = {{0.0, 0.0, 0.0},    {0.12, -0.07, 0.1},    {-0.17, 0.22, -0.2},
                            {0.28, 0.27, 0.33}, {-0.29, -0.28, -0.34}, {0.29, -0.02, 0.34}};
  for (const Pose2d& offset : offsets) {
    const Pose2d prediction{truth.x_m - offset.x_m, truth.y_m - offset.y_m,
                            truth.yaw_rad - offset.yaw_rad};
    const ScanMatchResult result = matcher.Match(map, *points, prediction, SearchWindow{});
    ASSERT_TRUE(result.found);
    // Translations are searched in 5 cm steps: up to 2.5 cm off, plus noise.
    EXPECT_NEAR(result.pose.x_m, truth.x_m, 0.035) << "offset " << offset;
    EXPECT_NEAR(result.pose.y_m, truth.y_m, 0.035) << "offset " << offset;
    EXPECT_NEAR(result.pose.yaw_rad, truth.yaw_rad, 0.01) << "offset " << offset;
    EXPECT_GT(result.response, 0.6) << "offset " << offset;
    // The sub-cell refinement does better than the lattice.
    EXPECT_NEAR(result.refined_pose.x_m, truth.x_m, 0.015) << "offset " << offset;
    EXPECT_NEAR(result.refined_pose.y_m, truth.y_m, 0.015) << "offset " << offset;
    EXPECT_NEAR(result.refined_pose.yaw_rad, truth.yaw_rad, 0.008) << "offset " << offset;
    EXPECT_LE(result.response, 1.0);
  }
}

TEST(ScanMatcherTest, RecoversLoopClosureOffsetInWideWindow) {
  Scanner scanner(FurnishedRoom());
  ScanMatcherOptions options;
  const CorrelationMap map = MapFrom(&scanner, {{3.5, 4.0, 0.0}, {3.8, 4.2, 0.3}}, options);
  const ScanMatcher matcher(options);
  const Pose2d truth{4.0, 4.5, -0.4};
  const ScanMatchResult result =
      matcher.Match(map, *scanner.Points(truth), {5.3, 3.1, -0.85}, SearchWindow{1.8, 0.5});
  ASSERT_TRUE(result.found);
  EXPECT_NEAR(result.pose.x_m, truth.x_m, 0.03);
  EXPECT_NEAR(result.pose.y_m, truth.y_m, 0.03);
  EXPECT_NEAR(result.pose.yaw_rad, truth.yaw_rad, 0.01);
}

// The score of the header's contract at offset (i, k) cells, j steps from
// the prediction, computed the plain way.
double ContractScore(const CorrelationMap& map, const PointCloud2d& points,
                     const Pose2d& prediction, const SearchWindow& window,
                     const ScanMatcherOptions& options, int i, int k, int j) {
  const Pose2d pose{prediction.x_m + i * options.resolution_m,
                    prediction.y_m + k * options.resolution_m,
                    prediction.yaw_rad + j * options.angular_step_rad};
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  double sum = 0.0;
  for (const Point2d& p : points) {  // pose.Transform(p) with sin and cos hoisted
    sum += map.Likelihood({pose.x_m + c * p.x_m - s * p.y_m, pose.y_m + s * p.x_m + c * p.y_m});
  }
  const double dt2 = (i * i + k * k) * options.resolution_m * options.resolution_m;
  const double dyaw = j * options.angular_step_rad;
  return sum / points.size() -
         options.window_edge_penalty * (dt2 / (window.linear_m * window.linear_m) +
                                        dyaw * dyaw / (window.angular_rad * window.angular_rad));
}

struct Exhaustive {
  double score = -std::numeric_limits<double>::infinity();
  int64_t poses = 0;
};
Exhaustive ExhaustiveSearch(const CorrelationMap& map, const PointCloud2d& points,
                            const Pose2d& prediction, const SearchWindow& window,
                            const ScanMatcherOptions& options) {
  const int n = static_cast<int>(std::ceil(window.linear_m / options.resolution_m - 1e-9));
  const int m = static_cast<int>(std::ceil(window.angular_rad / options.angular_step_rad - 1e-9));
  Exhaustive best;
  for (int j = -m; j <= m; ++j) {
    for (int i = -n; i <= n; ++i) {
      for (int k = -n; k <= n; ++k) {
        best.score =
            std::max(best.score, ContractScore(map, points, prediction, window, options, i, k, j));
        ++best.poses;
      }
    }
  }
  return best;
}

TEST(ScanMatcherTest, CoarseToFineEqualsExhaustiveSearch) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  struct Case {
    bool corridor;  // near-ties along the corridor punish any over-pruning
    SearchWindow window;
    double penalty;
  };
  // Narrow and wide windows (the wide one needs several blocks of the top
  // level per rotation), with and without the penalty.
  for (const Case& c :
       {Case{false, {0.3, 0.1}, 0.0}, Case{false, {0.3, 0.1}, 0.02}, Case{false, {0.8, 0.1}, 0.0},
        Case{false, {0.8, 0.1}, 0.02}, Case{true, {0.3, 0.1}, 0.0}, Case{true, {0.3, 0.1}, 0.02}}) {
    Scanner scanner(c.corridor ? WalledRoom(40.0, 2.0) : FurnishedRoom());
    const Pose2d center = c.corridor ? Pose2d{20.0, 2.0, 0.0} : Pose2d{6.5, 4.5, 0.0};
    ScanMatcherOptions options;
    options.angular_step_rad = 0.01;
    options.window_edge_penalty = c.penalty;
    const CorrelationMap map = MapFrom(
        &scanner, {center * Pose2d{-0.5, 0.5, 0.5}, center * Pose2d{-0.2, 0.3, 0.3}}, options);
    const ScanMatcher matcher(options);
    for (int trial = 0; trial < 4; ++trial) {
      const Pose2d truth = center * Pose2d{0.5 * unit(rng), 0.5 * unit(rng), 0.3 * unit(rng)};
      // Thinner scans keep the exhaustive search quick.
      const auto points = scanner.Points(truth, 0.15);
      const Pose2d prediction{truth.x_m + c.window.linear_m * unit(rng),
                              truth.y_m + c.window.linear_m * unit(rng),
                              truth.yaw_rad + c.window.angular_rad * unit(rng)};
      const ScanMatchResult result = matcher.Match(map, *points, prediction, c.window);
      const Exhaustive expected = ExhaustiveSearch(map, *points, prediction, c.window, options);
      SCOPED_TRACE(testing::Message()
                   << "corridor " << c.corridor << " window " << c.window.linear_m << " penalty "
                   << c.penalty << " trial " << trial);
      ASSERT_TRUE(result.found);
      // The returned pose is on the lattice and scores the maximum (ties may
      // pick another pose with the same score).
      const double i = (result.pose.x_m - prediction.x_m) / options.resolution_m;
      const double k = (result.pose.y_m - prediction.y_m) / options.resolution_m;
      const double j = (result.pose.yaw_rad - prediction.yaw_rad) / options.angular_step_rad;
      ASSERT_NEAR(i, std::round(i), 1e-6);
      ASSERT_NEAR(k, std::round(k), 1e-6);
      ASSERT_NEAR(j, std::round(j), 1e-6);
      EXPECT_NEAR(ContractScore(map, *points, prediction, c.window, options, std::lround(i),
                                std::lround(k), std::lround(j)),
                  expected.score, 1e-9);
      double sum = 0.0;
      for (const Point2d& p : *points) sum += map.Likelihood(result.pose.Transform(p));
      EXPECT_NEAR(result.response, sum / points->size(), 1e-9);
      // The pyramid must have pruned most of the fine poses.
      EXPECT_LT(result.candidates_scored, expected.poses / 4);
    }
  }
}

TEST(ScanMatcherTest, CovarianceIsLargeAlongACorridorOnly) {
  // A 40 m corridor, 2 m wide, along x: its ends are out of lidar range.
  Scanner scanner(WalledRoom(40.0, 2.0));
  ScanMatcherOptions options;
  const CorrelationMap map =
      MapFrom(&scanner, {{19.4, 2.0, 0.0}, {19.7, 2.1, 0.05}, {20.0, 2.0, 0.0}}, options);
  const ScanMatcher matcher(options);
  const Pose2d truth{20.3, 1.9, 0.02};
  const Pose2d prediction{20.4, 1.95, 0.07};
  const ScanMatchResult result =
      matcher.Match(map, *scanner.Points(truth), prediction, SearchWindow{});
  ASSERT_TRUE(result.found);
  EXPECT_NEAR(result.pose.y_m, truth.y_m, 0.03);
  EXPECT_NEAR(result.pose.yaw_rad, truth.yaw_rad, 0.01);
  // Nothing fixes x: the penalty keeps it at the prediction.
  EXPECT_NEAR(result.pose.x_m, prediction.x_m, 0.051);
  const Eigen::Matrix3d& cov = result.covariance;
  EXPECT_GT(cov(0, 0), 20.0 * cov(1, 1)) << cov;
  EXPECT_GT(cov(0, 0), 0.01) << cov;  // sigma along > 10 cm
  EXPECT_EQ(Eigen::LLT<Eigen::Matrix3d>(cov).info(), Eigen::Success);
}

TEST(ScanMatcherTest, CovarianceIsSmallInARoomCorner) {
  Scanner scanner(WalledRoom(4.0, 3.0));
  ScanMatcherOptions options;
  const CorrelationMap map = MapFrom(&scanner, {{1.6, 1.5, 0.0}, {1.9, 1.6, 0.3}}, options);
  const ScanMatcher matcher(options);
  const Pose2d truth{1.7, 1.4, 0.2};
  const ScanMatchResult result =
      matcher.Match(map, *scanner.Points(truth), {1.8, 1.5, 0.1}, SearchWindow{});
  ASSERT_TRUE(result.found);
  EXPECT_NEAR(result.pose.x_m, truth.x_m, 0.03);
  EXPECT_NEAR(result.pose.y_m, truth.y_m, 0.03);
  const Eigen::Matrix3d& cov = result.covariance;
  EXPECT_LT(cov(0, 0), 0.03 * 0.03) << cov;
  EXPECT_LT(cov(1, 1), 0.03 * 0.03) << cov;
  EXPECT_LT(cov(2, 2), 0.02 * 0.02) << cov;  // one cell at 2.5 m
  // The floor keeps it invertible.
  EXPECT_GE(cov(0, 0), options.min_stddev_m * options.min_stddev_m);
  EXPECT_GE(cov(2, 2), options.min_stddev_rad * options.min_stddev_rad);
  EXPECT_EQ(Eigen::LLT<Eigen::Matrix3d>(cov).info(), Eigen::Success);
}

}  // namespace
}  // namespace aslam
