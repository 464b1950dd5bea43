#pragma once

// Correlative scan matching (Olson, "Real-Time Correlative Scan Matching",
// ICRA 2009): an exhaustive search of a pose window against a smeared
// likelihood field of a local map, coarse-to-fine, with the covariance
// estimated from the response surface.

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
// `min_spacing_m` apart. Beams that fail LidarScan::IsValidReturn are skipped.
PointCloud2d ScanToPoints(const LidarScan& scan, double min_spacing_m);

// A scan placed in "map": the pieces a local map is built from.
struct PosedPoints {
  Pose2d pose;                                 // base in "map"
  std::shared_ptr<const PointCloud2d> points;  // in the base frame
};

struct ScanMatcherOptions {
  double resolution_m = 0.05;         // fine likelihood grid and finest translation step
  double smear_sigma_m = 0.05;        // std-dev of the Gaussian smear of map points
  int coarse_factor = 6;              // coarse grid cell = coarse_factor * resolution_m
  double angular_step_rad = 0.0;      // 0: chosen from the scan's extent (~resolution / max range)
  double max_point_range_m = 12.0;    // points farther away are not matched
};

// Half-widths of the search around the prediction.
struct SearchWindow {
  double linear_m = 0.3;
  double angular_rad = 0.35;
};

struct ScanMatchResult {
  bool found = false;      // false when the map or the scan is empty
  Pose2d pose;             // best pose of the base in "map"
  double response = 0.0;   // mean likelihood of the scan points at `pose`, in [0, 1]
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // over (x_m, y_m, yaw_rad)
};

// The likelihood field of a local map at the fine resolution plus its coarse
// max-pooled pyramid level; built once, matched against many times.
class CorrelationMap {
 public:
  CorrelationMap(const std::vector<PosedPoints>& scans, const ScanMatcherOptions& options);
  ~CorrelationMap();
  CorrelationMap(CorrelationMap&&) noexcept;
  CorrelationMap& operator=(CorrelationMap&&) noexcept;

  bool empty() const;
  // Likelihood in [0, 1] at a point in "map" (0 off the grid).
  double Likelihood(const Point2d& point_m) const;

 private:
  friend class ScanMatcher;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class ScanMatcher {
 public:
  explicit ScanMatcher(ScanMatcherOptions options);

  // Best pose of `points_base` in `map` within `window` around `prediction`.
  ScanMatchResult Match(const CorrelationMap& map, const PointCloud2d& points_base,
                        const Pose2d& prediction, const SearchWindow& window) const;

  const ScanMatcherOptions& options() const { return options_; }

 private:
  ScanMatcherOptions options_;
};

}  // namespace aslam
