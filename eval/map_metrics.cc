#include "eval/map_metrics.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/quality.hpp>

namespace aslam {
namespace {

// Trinary thresholds of ROS map_saver (occupied_thresh 0.65, free_thresh
// 0.196 in SaveMap's map.yaml): the grey image is what a reader of map.pgm sees.
constexpr int kOccupiedMin = 65;  // cells >= this render occupied
constexpr int kFreeMax = 25;      // cells in 0..this render free

// map_server's grey levels, 0..255.
constexpr double kOccupiedGrey255 = 0.0;
constexpr double kFreeGrey255 = 255.0;
constexpr double kUnknownGrey255 = 205.0;

// OpenCV's QualitySSIM hard-codes Wang's stabilising constants for 8-bit
// images: C1 = (0.01·255)² = 6.5025 and C2 = (0.03·255)² = 58.5225
// (opencv_contrib modules/quality/src/qualityssim.cpp), whatever the input
// type. Fed [0, 1] values they would be 255² times too large against the
// means and variances and pull every SSIM towards 1 (black against white
// would score C1/(1 + C1) ≈ 0.87). Scaling our [0, 1] images by the dynamic
// range 255 it assumes gives SSIM with C1 = (0.01·L)², C2 = (0.03·L)² for
// L = 1, as in the paper; SSIM is invariant to that common scale otherwise.
constexpr double kSsimDynamicRange = 255.0;

double CellGrey255(int8_t value) {
  if (value >= kOccupiedMin) return kOccupiedGrey255;
  if (value >= 0 && value <= kFreeMax) return kFreeGrey255;
  return kUnknownGrey255;
}

std::string SizeText(const cv::Mat& image) {
  return std::to_string(image.cols) + "x" + std::to_string(image.rows);
}

// Both images as CV_64FC1; throws std::invalid_argument (bad input, not a
// broken invariant: the images may come from files) naming both sizes.
void CheckPair(const cv::Mat& a, const cv::Mat& b, const char* what, cv::Mat* a64, cv::Mat* b64) {
  const std::string sizes = "first image " + SizeText(a) + ", second " + SizeText(b);
  if (a.size() != b.size()) {
    throw std::invalid_argument(std::string(what) + ": images differ in size (" + sizes + ")");
  }
  if (a.empty()) throw std::invalid_argument(std::string(what) + ": empty images (" + sizes + ")");
  if (a.channels() != 1 || b.channels() != 1) {
    throw std::invalid_argument(std::string(what) + ": expected single-channel grey images, got " +
                                std::to_string(a.channels()) + " and " +
                                std::to_string(b.channels()) + " channels");
  }
  a.convertTo(*a64, CV_64F);
  b.convertTo(*b64, CV_64F);
}

}  // namespace

cv::Mat MapToGrey(const OccupancyGrid& map) {
  if (map.empty()) return cv::Mat();
  const int height = map.height_cells();
  cv::Mat image(height, map.width_cells(), CV_64FC1);
  for (int row = 0; row < height; ++row) {
    // Grid row 0 is the bottom; the image's top row is the grid's top, as in map.pgm.
    double* pixels = image.ptr<double>(height - 1 - row);
    for (int col = 0; col < map.width_cells(); ++col) {
      pixels[col] = CellGrey255(map.at({col, row})) / 255.0;
    }
  }
  return image;
}

OccupancyGrid ResampleOnGrid(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                             const OccupancyGrid& truth) {
  if (truth.empty()) return OccupancyGrid();
  OccupancyGrid resampled(truth.width_cells(), truth.height_cells(), truth.resolution_m(),
                          truth.origin_m(), OccupancyGrid::kUnknown);
  if (slam_map.empty()) return resampled;
  const Pose2d world_in_map = map_in_world.Inverse();
  for (int row = 0; row < truth.height_cells(); ++row) {
    for (int col = 0; col < truth.width_cells(); ++col) {
      const Point2d centre_in_map = world_in_map.Transform(truth.CellCenter({col, row}));
      resampled.at({col, row}) =
          slam_map.ValueOr(slam_map.WorldToCell(centre_in_map), OccupancyGrid::kUnknown);
    }
  }
  return resampled;
}

double GreySsim(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat a64;
  cv::Mat b64;
  CheckPair(a, b, "GreySsim", &a64, &b64);
  // CV_64F input stays CV_64F inside QualitySSIM (quality_utils::expand_mat),
  // so identical images give exactly 1.
  const cv::Scalar ssim = cv::quality::QualitySSIM::compute(a64 * kSsimDynamicRange,
                                                            b64 * kSsimDynamicRange, cv::noArray());
  return ssim[0];
}

double GreyRmse(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat a64;
  cv::Mat b64;
  CheckPair(a, b, "GreyRmse", &a64, &b64);
  const double sum_squares = cv::norm(a64, b64, cv::NORM_L2SQR);
  return std::sqrt(sum_squares / static_cast<double>(a64.total()));
}

MapQuality CompareMapToTruth(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                             const OccupancyGrid& truth) {
  if (truth.empty()) throw std::invalid_argument("CompareMapToTruth: empty truth map");
  const cv::Mat truth_grey = MapToGrey(truth);
  const cv::Mat slam_grey = MapToGrey(ResampleOnGrid(slam_map, map_in_world, truth));
  MapQuality quality;
  quality.ssim = GreySsim(slam_grey, truth_grey);
  quality.rmse = GreyRmse(slam_grey, truth_grey);
  return quality;
}

}  // namespace aslam
