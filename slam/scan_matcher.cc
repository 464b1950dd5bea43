#include "slam/scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace aslam {

PointCloud2d ScanToPoints(const LidarScan& scan, double min_spacing_m) {
  PointCloud2d points;
  points.reserve(scan.range_m.size());
  const double min_spacing_sq = min_spacing_m > 0.0 ? min_spacing_m * min_spacing_m : 0.0;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    const double range = scan.range_m[i];
    // IsValidReturn passes 0 when range_min is 0 and inf when range_max is.
    if (!scan.IsValidReturn(i) || !std::isfinite(range) || range <= 0.0) continue;
    const double angle = scan.BeamAngle(i);
    const Point2d point =
        scan.sensor_pose.Transform({range * std::cos(angle), range * std::sin(angle)});
    if (!points.empty()) {
      const double dx = point.x_m - points.back().x_m;
      const double dy = point.y_m - points.back().y_m;
      if (dx * dx + dy * dy < min_spacing_sq) continue;
    }
    points.push_back(point);
  }
  return points;
}

void ValidateScanMatcherOptions(const ScanMatcherOptions& o) {
  const auto require = [](bool ok, const char* field, double value) {
    if (!ok) {
      throw std::invalid_argument(std::string("scan matcher option ") + field + " = " +
                                  std::to_string(value) + " is out of range");
    }
  };
  require(o.resolution_m > 0.0, "resolution_m", o.resolution_m);
  require(o.smear_sigma_m > 0.0, "smear_sigma_m", o.smear_sigma_m);
  require(o.coarse_factor >= 2, "coarse_factor", o.coarse_factor);
  require(o.coarse_levels >= 0 && std::pow(o.coarse_factor, o.coarse_levels) <= 1024,
          "coarse_levels", o.coarse_levels);
  require(o.angular_step_rad >= 0.0, "angular_step_rad", o.angular_step_rad);
  require(o.max_point_range_m > 0.0, "max_point_range_m", o.max_point_range_m);
  require(o.window_edge_penalty >= 0.0, "window_edge_penalty", o.window_edge_penalty);
  require(o.covariance_response_gain >= 0.0, "covariance_response_gain",
          o.covariance_response_gain);
  require(o.covariance_radius_m >= 0.0, "covariance_radius_m", o.covariance_radius_m);
  require(o.covariance_radius_rad >= 0.0, "covariance_radius_rad", o.covariance_radius_rad);
  require(o.min_stddev_m > 0.0, "min_stddev_m", o.min_stddev_m);
  require(o.min_stddev_rad > 0.0, "min_stddev_rad", o.min_stddev_rad);
}

namespace {

// Options reaching the library unvalidated are a broken invariant (docs/architecture.md §8).
void CheckOptions(const ScanMatcherOptions& options) {
  try {
    ValidateScanMatcherOptions(options);
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "scan_matcher: %s\n", error.what());
    std::abort();
  }
}

// out(r, c) = max over src(r + a*stride, c + b*stride), 0 <= a, b < taps, cells
// off the grid left out: one pyramid level from the one below, separably.
cv::Mat PoolForward(const cv::Mat& src, int stride, int taps) {
  cv::Mat along_x = src.clone();
  for (int t = 1; t < taps; ++t) {
    const int shift = t * stride;
    if (shift >= src.cols) break;
    cv::Mat dst = along_x.colRange(0, src.cols - shift);
    cv::max(dst, src.colRange(shift, src.cols), dst);
  }
  cv::Mat out = along_x.clone();
  for (int t = 1; t < taps; ++t) {
    const int shift = t * stride;
    if (shift >= src.rows) break;
    cv::Mat dst = out.rowRange(0, src.rows - shift);
    cv::max(dst, along_x.rowRange(shift, src.rows), dst);
  }
  return out;
}

// Likelihoods are stored as 0..255: a quarter of the memory traffic of
// floats, and integer sums make coarse bounds and fine scores exact.
constexpr double kMaxCellValue = 255.0;

// Keeps cell indices of far-off points from overflowing when offsets are added.
int ClampedFloor(double value) {
  constexpr double kLimit = 1 << 28;
  return static_cast<int>(std::floor(std::clamp(value, -kLimit, kLimit)));
}

// The pyramid, outside the class so the search helpers below can take it.
struct LikelihoodPyramid {
  double resolution_m = 0.0;
  Point2d origin_m;  // lower-left corner of cell (0, 0)
  int width = 0;
  int height = 0;
  int coarse_factor = 1;
  // levels[k](row, col) = max of the fine field over the widths[k]-cell square
  // starting at (col, row): an upper bound for every translation in that block.
  // CV_8U (see kMaxCellValue); row = y index, row 0 at the smallest y.
  std::vector<cv::Mat> levels;
  std::vector<int> widths;  // coarse_factor^k
};

}  // namespace

struct CorrelationMap::Impl : LikelihoodPyramid {};

CorrelationMap::CorrelationMap(const std::vector<PosedPoints>& scans,
                               const ScanMatcherOptions& options)
    : impl_(std::make_unique<Impl>()) {
  CheckOptions(options);
  Impl& m = *impl_;
  m.resolution_m = options.resolution_m;
  m.coarse_factor = options.coarse_factor;

  const double max_range_sq = options.max_point_range_m * options.max_point_range_m;
  std::vector<Point2d> map_points;
  for (const PosedPoints& scan : scans) {
    if (!scan.points) continue;
    for (const Point2d& p : *scan.points) {
      if (p.x_m * p.x_m + p.y_m * p.y_m > max_range_sq) continue;
      map_points.push_back(scan.pose.Transform(p));
    }
  }
  if (map_points.empty()) return;

  double min_x = map_points[0].x_m, max_x = min_x, min_y = map_points[0].y_m, max_y = min_y;
  for (const Point2d& p : map_points) {
    min_x = std::min(min_x, p.x_m);
    max_x = std::max(max_x, p.x_m);
    min_y = std::min(min_y, p.y_m);
    max_y = std::max(max_y, p.y_m);
  }
  int top_width = 1;
  for (int k = 0; k < options.coarse_levels; ++k) top_width *= options.coarse_factor;
  // The field is cut to zero beyond 3 sigma; the pyramid needs top_width zero
  // cells below/left (a clamped index 0 must bound nothing) and one above/right.
  const int smear_cells =
      static_cast<int>(std::ceil(3.0 * options.smear_sigma_m / m.resolution_m)) + 1;
  const int pad_low = smear_cells + top_width;
  const int pad_high = smear_cells + 1;
  const double res = m.resolution_m;
  m.origin_m = {std::floor(min_x / res) * res - pad_low * res,
                std::floor(min_y / res) * res - pad_low * res};
  m.width = static_cast<int>(std::floor((max_x - m.origin_m.x_m) / res)) + 1 + pad_high;
  m.height = static_cast<int>(std::floor((max_y - m.origin_m.y_m) / res)) + 1 + pad_high;
  if (static_cast<double>(m.width) * m.height > 1e8) {
    std::fprintf(stderr, "scan_matcher: local map of %d x %d cells is not local\n", m.width,
                 m.height);
    std::abort();
  }

  // Olson's field is the max over map points of a Gaussian of the distance, a
  // grayscale dilation with a non-flat element that OpenCV lacks: stamp a
  // precomputed kernel, cut at 3 sigma, once per occupied cell.
  const int radius = smear_cells - 1;
  const double cutoff_sq = std::pow(3.0 * options.smear_sigma_m / res, 2);
  const double scale = -res * res / (2.0 * options.smear_sigma_m * options.smear_sigma_m);
  std::vector<std::pair<int, uint8_t>> kernel;  // (offset in the grid, value)
  for (int b = -radius; b <= radius; ++b) {
    for (int a = -radius; a <= radius; ++a) {
      const double d_sq = a * a + b * b;
      const long value = std::lround(kMaxCellValue * std::exp(d_sq * scale));
      if (d_sq <= cutoff_sq && value > 0) kernel.emplace_back(b * m.width + a, value);
    }
  }
  cv::Mat field(m.height, m.width, CV_8U, cv::Scalar(0));
  uint8_t* data = field.ptr<uint8_t>();
  for (const Point2d& p : map_points) {
    const int col = static_cast<int>(std::floor((p.x_m - m.origin_m.x_m) / res));
    const int row = static_cast<int>(std::floor((p.y_m - m.origin_m.y_m) / res));
    uint8_t* center = data + static_cast<std::size_t>(row) * m.width + col;
    if (*center == kMaxCellValue) continue;  // the cell is stamped already
    for (const auto& [offset, value] : kernel) center[offset] = std::max(center[offset], value);
  }
  // The pyramid's bounds rely on these bands being zero (the padding keeps
  // stamps out of them).
  field.rowRange(0, top_width).setTo(0);
  field.colRange(0, top_width).setTo(0);
  field.row(m.height - 1).setTo(0);
  field.col(m.width - 1).setTo(0);

  m.levels.push_back(field);
  m.widths.push_back(1);
  for (int k = 1; k <= options.coarse_levels; ++k) {
    m.levels.push_back(PoolForward(m.levels.back(), m.widths.back(), options.coarse_factor));
    m.widths.push_back(m.widths.back() * options.coarse_factor);
  }
}

CorrelationMap::~CorrelationMap() = default;
CorrelationMap::CorrelationMap(CorrelationMap&&) noexcept = default;
CorrelationMap& CorrelationMap::operator=(CorrelationMap&&) noexcept = default;

bool CorrelationMap::empty() const { return !impl_ || impl_->levels.empty(); }
Point2d CorrelationMap::origin_m() const { return impl_ ? impl_->origin_m : Point2d{}; }
int CorrelationMap::width_cells() const { return impl_ ? impl_->width : 0; }
int CorrelationMap::height_cells() const { return impl_ ? impl_->height : 0; }

double CorrelationMap::Likelihood(const Point2d& point_m) const {
  if (empty()) return 0.0;
  const Impl& m = *impl_;
  const int col = ClampedFloor((point_m.x_m - m.origin_m.x_m) / m.resolution_m);
  const int row = ClampedFloor((point_m.y_m - m.origin_m.y_m) / m.resolution_m);
  if (col < 0 || row < 0 || col >= m.width || row >= m.height) return 0.0;
  return m.levels[0].at<uint8_t>(row, col) / kMaxCellValue;
}

ScanMatcher::ScanMatcher(ScanMatcherOptions options) : options_(options) { CheckOptions(options_); }

namespace {

struct Candidate {
  int rotation = 0;  // index into the searched rotations
  int x = 0;         // translation offset from the prediction in fine cells
  int y = 0;         //   (at a coarse level: the lower-left of the block)
  double score = 0.0;
};

// One search: the scan's cells for every rotation, scored against a map.
class Search {
 public:
  Search(const LikelihoodPyramid& map, const PointCloud2d& points, const Pose2d& prediction,
         const SearchWindow& window, double angular_step_rad, const ScanMatcherOptions& options)
      : map_(map), num_points_(static_cast<int>(points.size())), step_rad_(angular_step_rad) {
    linear_cells_ = static_cast<int>(std::ceil(window.linear_m / map.resolution_m - 1e-9));
    angular_steps_ = static_cast<int>(std::ceil(window.angular_rad / step_rad_ - 1e-9));
    linear_cells_ = std::max(linear_cells_, 0);
    angular_steps_ = std::max(angular_steps_, 0);
    penalty_ = options.window_edge_penalty;
    inv_linear_sq_ = window.linear_m > 0.0 ? 1.0 / (window.linear_m * window.linear_m) : 0.0;
    inv_angular_sq_ =
        window.angular_rad > 0.0 ? 1.0 / (window.angular_rad * window.angular_rad) : 0.0;
    inv_points_ = 1.0 / (kMaxCellValue * num_points_);

    // Rotate once per yaw; translations are then integer cell shifts. Points
    // on the grid at every shift of the window are kept as linear indices
    // (no clamping), points off it at every shift are dropped (they score 0 at
    // every level), the few in between are clamped per lookup.
    const int num_rotations = 2 * angular_steps_ + 1;
    const int n = linear_cells_ + 1;  // one more for the sub-cell refinement
    inside_begin_.push_back(0);
    straddling_begin_.push_back(0);
    const double inv_res = 1.0 / map.resolution_m;
    for (int r = 0; r < num_rotations; ++r) {
      const double yaw = prediction.yaw_rad + (r - angular_steps_) * step_rad_;
      const double c = std::cos(yaw), s = std::sin(yaw);
      for (const Point2d& p : points) {
        const double x = prediction.x_m + c * p.x_m - s * p.y_m;
        const double y = prediction.y_m + s * p.x_m + c * p.y_m;
        const int col = ClampedFloor((x - map.origin_m.x_m) * inv_res);
        const int row = ClampedFloor((y - map.origin_m.y_m) * inv_res);
        if (col - n >= 0 && row - n >= 0 && col + n < map.width && row + n < map.height) {
          inside_.push_back(row * map.width + col);
        } else if (col + n >= 0 && row + n >= 0 && col - n < map.width && row - n < map.height) {
          straddling_cols_.push_back(col);
          straddling_rows_.push_back(row);
        }
      }
      inside_begin_.push_back(static_cast<int>(inside_.size()));
      straddling_begin_.push_back(static_cast<int>(straddling_cols_.size()));
    }
  }

  int linear_cells() const { return linear_cells_; }
  int angular_steps() const { return angular_steps_; }
  int num_rotations() const { return 2 * angular_steps_ + 1; }
  int64_t scored() const { return scored_; }

  // Mean of level `level` over the points of rotation r shifted by (x, y)
  // cells, |x|, |y| <= linear_cells() + 1.
  double MeanAt(int level, int r, int x, int y) {
    ++scored_;
    const cv::Mat& grid = map_.levels[level];
    const uint8_t* data = grid.ptr<uint8_t>();
    const int width = map_.width, max_col = map_.width - 1, max_row = map_.height - 1;
    const int offset = y * width + x;
    uint32_t sum = 0;
    for (int i = inside_begin_[r]; i < inside_begin_[r + 1]; ++i) sum += data[inside_[i] + offset];
    // Off-grid indices clamp onto the zero border (see CorrelationMap).
    for (int i = straddling_begin_[r]; i < straddling_begin_[r + 1]; ++i) {
      const int col = std::clamp(straddling_cols_[i] + x, 0, max_col);
      const int row = std::clamp(straddling_rows_[i] + y, 0, max_row);
      sum += data[row * width + col];
    }
    return sum * inv_points_;
  }

  // The smallest penalty over a block of `width` cells from (x, y) at rotation r.
  double MinPenalty(int r, int x, int y, int width) const {
    if (penalty_ == 0.0) return 0.0;
    const auto min_sq = [this, width](int lo) {
      const int hi = std::min(lo + width - 1, linear_cells_);
      if (lo <= 0 && hi >= 0) return 0.0;
      const double nearest = lo > 0 ? lo : hi;
      return nearest * nearest;
    };
    const double res = map_.resolution_m;
    const double yaw = (r - angular_steps_) * step_rad_;
    return penalty_ *
           ((min_sq(x) + min_sq(y)) * res * res * inv_linear_sq_ + yaw * yaw * inv_angular_sq_);
  }

  Candidate Score(int level, int r, int x, int y) {
    return {r, x, y, MeanAt(level, r, x, y) - MinPenalty(r, x, y, map_.widths[level])};
  }

  // Depth-first branch and bound: a block whose bound cannot beat the best
  // leaf so far is dropped, so the result is the exhaustive maximum.
  void BranchAndBound(int level, std::vector<Candidate>* candidates, Candidate* best) {
    std::sort(candidates->begin(), candidates->end(),
              [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    for (const Candidate& candidate : *candidates) {
      if (candidate.score <= best->score) break;
      if (level == 0) {
        *best = candidate;
        continue;
      }
      const int child_width = map_.widths[level - 1];
      std::vector<Candidate> children;
      children.reserve(map_.coarse_factor * map_.coarse_factor);
      for (int a = 0; a < map_.coarse_factor; ++a) {
        const int x = candidate.x + a * child_width;
        if (x > linear_cells_) break;
        for (int b = 0; b < map_.coarse_factor; ++b) {
          const int y = candidate.y + b * child_width;
          if (y > linear_cells_) break;
          children.push_back(Score(level - 1, candidate.rotation, x, y));
        }
      }
      BranchAndBound(level - 1, &children, best);
    }
  }

 private:
  const LikelihoodPyramid& map_;
  int num_points_ = 0;
  double step_rad_ = 0.0;
  int linear_cells_ = 0;
  int angular_steps_ = 0;
  double penalty_ = 0.0;
  double inv_linear_sq_ = 0.0;
  double inv_angular_sq_ = 0.0;
  double inv_points_ = 0.0;
  // Per rotation r, entries [begin[r], begin[r + 1]).
  std::vector<int32_t> inside_;  // row * width + col at zero shift
  std::vector<int> inside_begin_;
  std::vector<int32_t> straddling_cols_;
  std::vector<int32_t> straddling_rows_;
  std::vector<int> straddling_begin_;
  int64_t scored_ = 0;
};

}  // namespace

ScanMatchResult ScanMatcher::Match(const CorrelationMap& map, const PointCloud2d& points_base,
                                   const Pose2d& prediction, const SearchWindow& window) const {
  ScanMatchResult result;
  result.pose = prediction;
  if (map.empty()) return result;
  const LikelihoodPyramid& grid = *map.impl_;

  const double max_range_sq = options_.max_point_range_m * options_.max_point_range_m;
  PointCloud2d points;
  points.reserve(points_base.size());
  double farthest_m = 0.0;
  for (const Point2d& p : points_base) {
    const double range_sq = p.x_m * p.x_m + p.y_m * p.y_m;
    if (!(range_sq <= max_range_sq)) continue;  // also drops NaN
    points.push_back(p);
    farthest_m = std::max(farthest_m, std::sqrt(range_sq));
  }
  if (points.empty()) return result;

  // Olson: the step that moves the farthest point by one cell.
  double step_rad = options_.angular_step_rad;
  if (step_rad <= 0.0) {
    const double reach_m = std::max(farthest_m, 2.0 * grid.resolution_m);
    step_rad = std::acos(1.0 - grid.resolution_m * grid.resolution_m / (2.0 * reach_m * reach_m));
  }
  result.angular_step_rad = step_rad;

  Search search(grid, points, prediction, window, step_rad, options_);
  const int n = search.linear_cells();

  // Start at the finest level whose one block covers the window, or the
  // coarsest (measured: far coarser blocks bound every rotation by ~1 and
  // prune worse, so coarse_levels stays moderate).
  int top = 0;
  while (top + 1 < static_cast<int>(grid.widths.size()) && grid.widths[top] < 2 * n + 1) ++top;
  const int top_width = grid.widths[top];
  std::vector<Candidate> candidates;
  for (int r = 0; r < search.num_rotations(); ++r) {
    for (int x = -n; x <= n; x += top_width) {
      for (int y = -n; y <= n; y += top_width) candidates.push_back(search.Score(top, r, x, y));
    }
  }
  Candidate best;
  best.score = -std::numeric_limits<double>::infinity();
  search.BranchAndBound(top, &candidates, &best);

  const double res = grid.resolution_m;
  const int best_yaw_steps = best.rotation - search.angular_steps();
  result.pose = {prediction.x_m + best.x * res, prediction.y_m + best.y * res,
                 WrapAngle(prediction.yaw_rad + best_yaw_steps * step_rad)};
  result.candidates_scored = search.scored();
  const double best_response = search.MeanAt(0, best.rotation, best.x, best.y);
  result.response = best_response;
  result.found = best_response > 0.0;

  // Sub-cell peak: a parabola through the best and its two neighbours, per
  // axis (yaw: not at the window's edge, its neighbour is not rotated).
  const auto vertex = [best_response](double before, double after) {
    const double curvature = before - 2.0 * best_response + after;
    if (curvature >= 0.0) return 0.0;  // not a peak along this axis
    return std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5);
  };
  const double sub_x = vertex(search.MeanAt(0, best.rotation, best.x - 1, best.y),
                              search.MeanAt(0, best.rotation, best.x + 1, best.y));
  const double sub_y = vertex(search.MeanAt(0, best.rotation, best.x, best.y - 1),
                              search.MeanAt(0, best.rotation, best.x, best.y + 1));
  double sub_yaw = 0.0;
  if (best.rotation > 0 && best.rotation + 1 < search.num_rotations()) {
    sub_yaw = vertex(search.MeanAt(0, best.rotation - 1, best.x, best.y),
                     search.MeanAt(0, best.rotation + 1, best.x, best.y));
  }
  result.refined_pose = {result.pose.x_m + sub_x * res, result.pose.y_m + sub_y * res,
                         WrapAngle(result.pose.yaw_rad + sub_yaw * step_rad)};

  // Olson §IV: the response-weighted second moment of poses around the best,
  // on a lattice inside the window: every fine translation (a peak one cell
  // wide must show) and at most 7 rotations.
  const int cov_cells =
      std::min(n, static_cast<int>(std::ceil(options_.covariance_radius_m / res)));
  const int cov_steps =
      std::min(search.angular_steps(),
               static_cast<int>(std::ceil(options_.covariance_radius_rad / step_rad)));
  const int step_stride = std::max(1, (cov_steps + 2) / 3);
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  double weight_sum = 0.0;
  for (int dr = -cov_steps; dr <= cov_steps; dr += step_stride) {
    const int r = best.rotation + dr;
    if (r < 0 || r >= search.num_rotations()) continue;
    for (int dx = -cov_cells; dx <= cov_cells; ++dx) {
      if (std::abs(best.x + dx) > n) continue;
      for (int dy = -cov_cells; dy <= cov_cells; ++dy) {
        if (std::abs(best.y + dy) > n) continue;
        const double response = search.MeanAt(0, r, best.x + dx, best.y + dy);
        const double weight =
            std::exp(options_.covariance_response_gain * (response - best_response));
        const Eigen::Vector3d delta(dx * res, dy * res, dr * step_rad);
        moment += weight * delta * delta.transpose();
        weight_sum += weight;
      }
    }
  }
  result.covariance = moment / weight_sum;  // the best itself has weight 1
  result.covariance.diagonal() += Eigen::Vector3d(
      options_.min_stddev_m * options_.min_stddev_m, options_.min_stddev_m * options_.min_stddev_m,
      options_.min_stddev_rad * options_.min_stddev_rad);
  return result;
}

}  // namespace aslam
