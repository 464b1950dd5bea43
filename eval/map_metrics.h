#pragma once

// Map quality of docs/architecture.md §6 for the paper's Table I: SSIM and RMSE between the
// SLAM map and the ground-truth map, both rendered as grey images on the
// truth's grid. Pure C++, no LCM: the runner and the bench tools feed it
// decoded grids.
//
// Frames: the SLAM map is in "map", the truth in "world"; `map_in_world` (the
// true pose of the first keyframe) places one in the other, as in
// ComputeMapAgreement (eval/trajectory_metrics.h).

#include <opencv2/core.hpp>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {

// The grid as a grey image (CV_64FC1, values in [0, 1]): occupied
// (v >= 65) 0, free (0 <= v <= 25) 1, anything else (unknown −1 and the
// undecided 26..64) 205/255. Image row 0 is the grid's top row (largest y),
// as in map.pgm, so the image reads like the saved map. An empty grid gives
// an empty image.
cv::Mat MapToGrey(const OccupancyGrid& map);

// The SLAM map (frame "map") resampled on `truth`'s grid (frame "world"):
// same size, resolution and origin as `truth`; each truth cell centre is
// carried into "map" by map_in_world⁻¹ and takes the value of the SLAM cell
// it falls in (nearest-cell lookup, no interpolation, so values stay cell
// values); −1 where it falls outside the SLAM map. An empty truth gives an
// empty grid.
OccupancyGrid ResampleOnGrid(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                             const OccupancyGrid& truth);

// SSIM (Wang et al. 2004) of two same-size single-channel grey images with
// values in [0, 1], by OpenCV's cv::quality::QualitySSIM (11x11 Gaussian
// window, sigma 1.5, mean over the whole image). 1 for identical images.
// Throws std::invalid_argument naming both sizes if they differ, or if an
// image is empty or has more than one channel.
double GreySsim(const cv::Mat& a, const cv::Mat& b);

// Root mean square of the per-pixel difference of two same-size
// single-channel grey images with values in [0, 1]; in [0, 1]. Throws like
// GreySsim.
double GreyRmse(const cv::Mat& a, const cv::Mat& b);

struct MapQuality {
  double ssim = 0.0;  // 1 is a perfect map
  double rmse = 0.0;  // grey levels in [0, 1]; 0 is a perfect map
};

// Both metrics of the SLAM map against the truth, on the truth's grid: the
// SLAM map is resampled there (ResampleOnGrid), so the parts of the building
// it has not explored count against it as unknown grey. Throws
// std::invalid_argument for an empty truth.
MapQuality CompareMapToTruth(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                             const OccupancyGrid& truth);

}  // namespace aslam
