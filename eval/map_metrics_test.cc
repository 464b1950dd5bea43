#include "eval/map_metrics.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "eval/trajectory_metrics.h"

namespace aslam {
namespace {

constexpr double kUnknownGrey = 205.0 / 255.0;
// Wang et al.'s C1 = (0.01·L)² and C2 = (0.03·L)² for a dynamic range L = 1.
constexpr double kC1 = 0.01 * 0.01;

// A free map with a solid occupied square: walls thick enough that a shift
// of a few cells moves edges without making them cross each other.
OccupancyGrid BlockMap(int shift_cells) {
  OccupancyGrid map(60, 60, 0.05, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int row = 20; row < 40; ++row) {
    for (int col = 20 + shift_cells; col < 40 + shift_cells; ++col) {
      map.at({col, row}) = OccupancyGrid::kOccupied;
    }
  }
  return map;
}

// Cell values that name their cell: 10·row + col (all in 0..100).
OccupancyGrid NumberedMap(int width_cells, int height_cells, double resolution_m,
                          Point2d origin_m) {
  OccupancyGrid map(width_cells, height_cells, resolution_m, origin_m);
  for (int row = 0; row < height_cells; ++row) {
    for (int col = 0; col < width_cells; ++col) {
      map.at({col, row}) = static_cast<int8_t>(10 * row + col);
    }
  }
  return map;
}

std::string ThrownMessage(double (*metric)(const cv::Mat&, const cv::Mat&), const cv::Mat& a,
                          const cv::Mat& b) {
  try {
    metric(a, b);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(MapToGreyTest, RendersTrinaryLevelsAtMapSaverThresholds) {
  const int8_t values[] = {-1, 0, 25, 26, 64, 65, 100};
  // Unknown, free, free (last free), undecided, undecided (last), occupied, occupied.
  const double expected[] = {kUnknownGrey, 1.0, 1.0, kUnknownGrey, kUnknownGrey, 0.0, 0.0};
  OccupancyGrid map(7, 1, 0.1, {0.0, 0.0});
  for (int col = 0; col < 7; ++col) map.at({col, 0}) = values[col];

  const cv::Mat grey = MapToGrey(map);
  ASSERT_EQ(grey.type(), CV_64FC1);
  ASSERT_EQ(grey.rows, 1);
  ASSERT_EQ(grey.cols, 7);
  for (int col = 0; col < 7; ++col) {
    EXPECT_DOUBLE_EQ(grey.at<double>(0, col), expected[col]) << "cell value " << int{values[col]};
  }
}

TEST(MapToGreyTest, TopGridRowIsFirstImageRow) {
  OccupancyGrid map(1, 2, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  map.at({0, 1}) = OccupancyGrid::kOccupied;  // top of the grid (larger y)
  const cv::Mat grey = MapToGrey(map);
  EXPECT_EQ(grey.at<double>(0, 0), 0.0);  // as in map.pgm: the top row comes first
  EXPECT_EQ(grey.at<double>(1, 0), 1.0);
}

TEST(MapToGreyTest, EmptyGridGivesEmptyImage) { EXPECT_TRUE(MapToGrey(OccupancyGrid()).empty()); }

TEST(GreySsimTest, IdenticalMapsScoreOne) {
  const cv::Mat grey = MapToGrey(BlockMap(0));
  EXPECT_NEAR(GreySsim(grey, grey), 1.0, 1e-9);
  EXPECT_NEAR(GreySsim(grey, grey.clone()), 1.0, 1e-9);
}

TEST(GreySsimTest, ConstantImagesUseUnitDynamicRange) {
  // Two constant images have no variance, so SSIM reduces to the luminance
  // term (2·μa·μb + C1) / (μa² + μb² + C1) with Wang's C1 = (0.01·L)², L = 1.
  // OpenCV's 8-bit constants fed [0, 1] values would give C1' / (1 + C1') ≈ 0.87
  // for black against white instead.
  const cv::Mat white(10, 12, CV_64FC1, cv::Scalar(1.0));
  const cv::Mat black(10, 12, CV_64FC1, cv::Scalar(0.0));
  const cv::Mat grey(10, 12, CV_64FC1, cv::Scalar(kUnknownGrey));
  EXPECT_NEAR(GreySsim(white, black), kC1 / (1.0 + kC1), 1e-9);
  EXPECT_NEAR(GreySsim(white, grey),
              (2.0 * kUnknownGrey + kC1) / (1.0 + kUnknownGrey * kUnknownGrey + kC1), 1e-9);
}

TEST(GreySsimTest, DropsAsTheMapShiftsFurther) {
  // Each extra cell of shift uncovers another 20-cell column on both sides of
  // the block, and the local windows there lose correlation.
  const cv::Mat truth = MapToGrey(BlockMap(0));
  const double ssim_1 = GreySsim(MapToGrey(BlockMap(1)), truth);
  const double ssim_2 = GreySsim(MapToGrey(BlockMap(2)), truth);
  const double ssim_4 = GreySsim(MapToGrey(BlockMap(4)), truth);
  EXPECT_LT(ssim_1, 0.99);
  EXPECT_LT(ssim_2, ssim_1);
  EXPECT_LT(ssim_4, ssim_2);
  EXPECT_GT(ssim_4, 0.0);  // most of the map is still right
}

TEST(GreyRmseTest, IdenticalMapsScoreZero) {
  const cv::Mat grey = MapToGrey(BlockMap(0));
  EXPECT_EQ(GreyRmse(grey, grey), 0.0);
}

TEST(GreyRmseTest, FreeVersusOccupiedCellsDifferByOne) {
  // k cells differ by a full grey step (1.0): RMSE = sqrt(k / N).
  const OccupancyGrid truth(10, 8, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  OccupancyGrid slam = truth;
  const CellIndex wrong[] = {{0, 0}, {9, 7}, {3, 4}, {5, 5}, {6, 1}, {2, 7}, {8, 3}};
  for (const CellIndex& cell : wrong) slam.at(cell) = OccupancyGrid::kOccupied;
  EXPECT_NEAR(GreyRmse(MapToGrey(slam), MapToGrey(truth)), std::sqrt(7.0 / 80.0), 1e-12);
}

TEST(GreyRmseTest, FreeVersusUnknownCellsDifferBy50Of255) {
  // Free 255 against unknown 205 (or undecided 26..64, same grey):
  // RMSE = (50/255)·sqrt(k / N).
  const OccupancyGrid truth(10, 8, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  OccupancyGrid slam = truth;
  slam.at({1, 1}) = OccupancyGrid::kUnknown;
  slam.at({2, 1}) = OccupancyGrid::kUnknown;
  slam.at({3, 1}) = OccupancyGrid::kUnknown;
  slam.at({4, 6}) = 40;
  slam.at({7, 2}) = 50;
  EXPECT_NEAR(GreyRmse(MapToGrey(slam), MapToGrey(truth)), 50.0 / 255.0 * std::sqrt(5.0 / 80.0),
              1e-12);
}

TEST(GreyMetricsTest, MismatchedSizesThrowNamingBothSizes) {
  const cv::Mat a(8, 10, CV_64FC1, cv::Scalar(1.0));  // 10 wide, 8 high
  const cv::Mat b(8, 12, CV_64FC1, cv::Scalar(1.0));  // 12 wide, 8 high
  for (const std::string& message :
       {ThrownMessage(&GreySsim, a, b), ThrownMessage(&GreyRmse, a, b)}) {
    EXPECT_NE(message.find("10x8"), std::string::npos) << message;
    EXPECT_NE(message.find("12x8"), std::string::npos) << message;
  }
  EXPECT_THROW(GreySsim(cv::Mat(), cv::Mat()), std::invalid_argument);
  EXPECT_THROW(GreyRmse(cv::Mat(), cv::Mat()), std::invalid_argument);
}

TEST(ResampleOnGridTest, IdentityOnTheSameGridKeepsTheMap) {
  const OccupancyGrid slam = NumberedMap(7, 5, 0.05, {-1.3, 2.1});
  const OccupancyGrid resampled = ResampleOnGrid(slam, Pose2d(), slam);
  EXPECT_EQ(resampled.width_cells(), 7);
  EXPECT_EQ(resampled.height_cells(), 5);
  EXPECT_EQ(resampled.resolution_m(), 0.05);
  EXPECT_EQ(resampled.origin_m().x_m, -1.3);
  EXPECT_EQ(resampled.origin_m().y_m, 2.1);
  EXPECT_EQ(resampled.cells(), slam.cells());
}

TEST(ResampleOnGridTest, WholeCellTranslationShiftsCellIndices) {
  // SLAM grid 4x3 at (-1.0, 0.5), truth 8x6 at (0, 0), both 0.1 m. The map
  // origin sits at (1.2, -0.4) in the world, so SLAM cell (c, r), centred at
  // map ((c + 0.5)·0.1 - 1.0, (r + 0.5)·0.1 + 0.5), lands at world
  // ((c + 2.5)·0.1, (r + 1.5)·0.1): truth cell (c + 2, r + 1).
  const OccupancyGrid slam = NumberedMap(4, 3, 0.1, {-1.0, 0.5});
  const OccupancyGrid truth(8, 6, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  const OccupancyGrid resampled = ResampleOnGrid(slam, Pose2d{1.2, -0.4, 0.0}, truth);
  ASSERT_EQ(resampled.width_cells(), 8);
  ASSERT_EQ(resampled.height_cells(), 6);
  EXPECT_EQ(resampled.at({2, 1}), slam.at({0, 0}));
  EXPECT_EQ(resampled.at({5, 3}), slam.at({3, 2}));
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 8; ++col) {
      const CellIndex source{col - 2, row - 1};
      const int expected = slam.Contains(source) ? slam.at(source) : OccupancyGrid::kUnknown;
      EXPECT_EQ(resampled.at({col, row}), expected) << "truth cell " << col << "," << row;
    }
  }
}

TEST(ResampleOnGridTest, QuarterTurnRotatesCellIndices) {
  // map_in_world = yaw +90° about the common origin: map (x, y) is world
  // (-y, x). SLAM grid 4 wide x 3 high from (0, 0); truth 4 wide x 4 high from
  // (-0.3, 0), 0.1 m. SLAM cell (c, r), centred at map ((c + 0.5)·0.1,
  // (r + 0.5)·0.1), lands at world (-(r + 0.5)·0.1, (c + 0.5)·0.1): truth
  // cell (2 - r, c). Truth column 3 (world x > 0) is map y < 0: outside.
  const OccupancyGrid slam = NumberedMap(4, 3, 0.1, {0.0, 0.0});
  const OccupancyGrid truth(4, 4, 0.1, {-0.3, 0.0}, OccupancyGrid::kFree);
  const OccupancyGrid resampled = ResampleOnGrid(slam, Pose2d{0.0, 0.0, M_PI / 2.0}, truth);
  EXPECT_EQ(resampled.at({2, 0}), slam.at({0, 0}));
  EXPECT_EQ(resampled.at({2, 1}), slam.at({1, 0}));
  EXPECT_EQ(resampled.at({0, 3}), slam.at({3, 2}));
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) {
      EXPECT_EQ(resampled.at({2 - r, c}), slam.at({c, r})) << "slam cell " << c << "," << r;
    }
  }
  for (int row = 0; row < 4; ++row) EXPECT_EQ(resampled.at({3, row}), OccupancyGrid::kUnknown);
}

TEST(ResampleOnGridTest, FinerTruthGridTakesTheCellEachCentreFallsIn) {
  // Truth at half the SLAM resolution over the same area: each SLAM cell
  // covers a 2x2 block of truth cells.
  const OccupancyGrid slam = NumberedMap(3, 2, 0.1, {0.0, 0.0});
  const OccupancyGrid truth(6, 4, 0.05, {0.0, 0.0});
  const OccupancyGrid resampled = ResampleOnGrid(slam, Pose2d(), truth);
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 6; ++col) {
      EXPECT_EQ(resampled.at({col, row}), slam.at({col / 2, row / 2}));
    }
  }
}

TEST(ResampleOnGridTest, CellsOutsideTheSlamMapAreUnknown) {
  const OccupancyGrid slam(5, 5, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  const OccupancyGrid truth(5, 5, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  // Moved 10 m away: no truth centre falls on the SLAM map.
  const OccupancyGrid far = ResampleOnGrid(slam, Pose2d{10.0, 0.0, 0.0}, truth);
  EXPECT_EQ(far.CountCells().unknown, 25u);
  const OccupancyGrid none = ResampleOnGrid(OccupancyGrid(), Pose2d(), truth);
  EXPECT_EQ(none.CountCells().unknown, 25u);
}

TEST(CompareMapToTruthTest, PerfectMapScoresOneAndZero) {
  const OccupancyGrid truth = BlockMap(0);
  const MapQuality quality = CompareMapToTruth(truth, Pose2d(), truth);
  EXPECT_NEAR(quality.ssim, 1.0, 1e-9);
  EXPECT_EQ(quality.rmse, 0.0);
}

TEST(CompareMapToTruthTest, UnexploredHalfCountsAgainstTheMap) {
  // The SLAM map covers the left half of an all-free truth, correctly: the
  // right half resamples to unknown, 50/255 off in half the cells.
  const OccupancyGrid truth(20, 10, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  const OccupancyGrid slam(10, 10, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  const MapQuality quality = CompareMapToTruth(slam, Pose2d(), truth);
  EXPECT_NEAR(quality.rmse, 50.0 / 255.0 * std::sqrt(0.5), 1e-12);
  EXPECT_LT(quality.ssim, 1.0 - 1e-3);
}

TEST(CompareMapToTruthTest, BlankMapScoresTheUnknownLuminanceTerm) {
  // Nothing explored: the whole truth (all free) against uniform unknown grey.
  // Both images are constant, so SSIM is the luminance term alone.
  const OccupancyGrid truth(20, 10, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  const MapQuality quality = CompareMapToTruth(OccupancyGrid(), Pose2d(), truth);
  EXPECT_NEAR(quality.rmse, 50.0 / 255.0, 1e-12);
  EXPECT_NEAR(quality.ssim, (2.0 * kUnknownGrey + kC1) / (1.0 + kUnknownGrey * kUnknownGrey + kC1),
              1e-9);
}

// Coverage (docs/architecture.md §6, ComputeMapAgreement): a SLAM map over the left 10 of
// 20 free columns, shifted by map_in_world, knows exactly half the free truth.
TEST(CoverageTest, KnownPartialOverlap) {
  OccupancyGrid truth(20, 10, 0.1, {0.0, 0.0}, OccupancyGrid::kFree);
  for (int col = 0; col < 20; ++col)
    truth.at({col, 9}) = OccupancyGrid::kOccupied;  // a wall row: not free area
  const OccupancyGrid slam(10, 10, 0.1, {-0.5, 0.0}, OccupancyGrid::kFree);
  const MapAgreement a = ComputeMapAgreement(slam, Pose2d{0.5, 0.0, 0.0}, truth);
  EXPECT_EQ(a.truth_free_cells, 20 * 9);
  EXPECT_EQ(a.truth_free_known, 10 * 9);
  EXPECT_DOUBLE_EQ(a.coverage, 0.5);
}

TEST(CompareMapToTruthTest, EmptyTruthThrows) {
  EXPECT_THROW(CompareMapToTruth(BlockMap(0), Pose2d(), OccupancyGrid()), std::invalid_argument);
}

}  // namespace
}  // namespace aslam
