#pragma once

// Correlative scan matching (Olson, "Real-Time Correlative Scan Matching",
// ICRA 2009): an exhaustive search of a pose window against a smeared
// likelihood field of a local map, coarse-to-fine, with the covariance
// estimated from the response surface.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "common/pose2d.h"
#include "common/sensor_types.h"

namespace aslam {

// Scan end points in the robot base frame.
using PointCloud2d = std::vector<Point2d>;

// The valid returns of `scan` as points in the base frame (the sensor pose
// applied), thinned so consecutive kept points are at least
// `min_spacing_m` apart (<= 0 keeps all). Beams that fail
// LidarScan::IsValidReturn, and NaN, infinite, zero or negative ranges
// whatever the limits, are skipped.
PointCloud2d ScanToPoints(const LidarScan& scan, double min_spacing_m);

// A scan placed in "map": the pieces a local map is built from.
struct PosedPoints {
  Pose2d pose;                                 // base in "map"
  std::shared_ptr<const PointCloud2d> points;  // in the base frame
};

// Both CorrelationMap and ScanMatcher take these; a map's grid options
// (resolution, smear, pyramid) are the ones it was built with.
struct ScanMatcherOptions {
  double resolution_m = 0.05;       // fine likelihood grid and finest translation step
  double smear_sigma_m = 0.05;      // std-dev of the Gaussian smear of map points
  int coarse_factor = 2;            // pyramid level k pools coarse_factor^k fine cells a side
  double angular_step_rad = 0.0;    // 0: chosen from the scan's extent (~resolution / max range)
  double max_point_range_m = 12.0;  // points farther from their base are left out
  // Pyramid levels above the fine grid, level k pooling coarse_factor^k cells
  // a side. A search starts at the finest level whose block covers its window
  // (capped here: 2^5 cells = 1.6 m, measured fastest for wide windows).
  int coarse_levels = 5;
  // Score = response - window_edge_penalty * (|dt|^2 / linear^2 + dyaw^2 / angular^2)
  // over the offset from the prediction: flat responses (corridors) resolve
  // to the prediction instead of an arbitrary pose. Not in `response`.
  double window_edge_penalty = 0.02;
  // Covariance (Olson §IV): weights exp(gain * (response - best response))
  // on a pose lattice around the best, within these radii (clipped to the
  // window). A larger gain trusts small response differences more.
  double covariance_response_gain = 100.0;
  double covariance_radius_m = 0.3;
  double covariance_radius_rad = 0.1;
  // Added to the covariance diagonal: the grid cannot resolve finer than this.
  double min_stddev_m = 0.02;
  double min_stddev_rad = 0.005;
};

// Throws std::invalid_argument naming the first bad field and its value.
void ValidateScanMatcherOptions(const ScanMatcherOptions& options);

// Half-widths of the search around the prediction.
struct SearchWindow {
  double linear_m = 0.3;
  double angular_rad = 0.35;
};

struct ScanMatchResult {
  bool found = false;  // false when the map or the scan is empty, or nothing overlaps
  Pose2d pose;         // best pose of the base in "map"
  // `pose` moved to the vertex of a parabola through the responses of its
  // neighbours, per axis: finer than the search lattice.
  Pose2d refined_pose;
  double response = 0.0;  // mean likelihood of the scan points at `pose`, in [0, 1]
  // Over (x_m, y_m, yaw_rad) of `pose` in the "map" axes (not the base's):
  // the response-weighted second moment plus the min_stddev floors, so
  // invertible; large along a corridor, small across it.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  double angular_step_rad = 0.0;  // the rotation step searched
  int64_t candidates_scored = 0;  // (level, pose) candidates the search scored: its cost
};

// The likelihood field of a local map at the fine resolution (a map point's
// cell 1, exp(-d^2 / 2 sigma^2) around it, 0 beyond 3 sigma; stored in steps
// of 1/255) plus its max-pooled pyramid; built once, matched against many
// times. Aborts on invalid options (validate them at load time).
class CorrelationMap {
 public:
  CorrelationMap(const std::vector<PosedPoints>& scans, const ScanMatcherOptions& options);
  ~CorrelationMap();
  CorrelationMap(CorrelationMap&&) noexcept;
  CorrelationMap& operator=(CorrelationMap&&) noexcept;

  bool empty() const;
  // Fine grid geometry: cell (col, row) covers origin + [col, col+1) * resolution.
  Point2d origin_m() const;
  int width_cells() const;
  int height_cells() const;
  // Likelihood in [0, 1] at a point in "map" (0 off the grid).
  double Likelihood(const Point2d& point_m) const;

 private:
  friend class ScanMatcher;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class ScanMatcher {
 public:
  // Aborts on invalid options (validate them at load time).
  explicit ScanMatcher(ScanMatcherOptions options);

  // Best pose of `points_base` in `map` within `window` around `prediction`.
  // Searched: yaw = prediction.yaw + j * step for |j| <= ceil(angular / step),
  // translation = prediction + (i, k) * resolution for |i|, |k| <= ceil(linear /
  // resolution); a point scores the fine cell of its pose at (i, k) = 0
  // shifted by (i, k) cells. The result maximises the score exactly, as an
  // exhaustive search would (branch and bound over the max-pooled pyramid).
  // Const and free of shared state: threads may match concurrently.
  ScanMatchResult Match(const CorrelationMap& map, const PointCloud2d& points_base,
                        const Pose2d& prediction, const SearchWindow& window) const;

  const ScanMatcherOptions& options() const { return options_; }

 private:
  ScanMatcherOptions options_;
};

}  // namespace aslam
