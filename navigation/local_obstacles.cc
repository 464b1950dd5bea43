#include "navigation/local_obstacles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

namespace aslam {
namespace {

template <typename T>
[[noreturn]] void ThrowBadOption(const std::string& name, T value, const std::string& why) {
  std::ostringstream message;
  message << "LocalObstaclesOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

// A grid edge this close to a cell boundary counts as on it (float noise).
constexpr double kBoundaryEpsilonCells = 1e-6;

// For each source cell along one axis, the window cells it overlaps
// (first, last; first > last when none).
struct CellSpan {
  int first = 0;
  int last = -1;
};

std::vector<CellSpan> OverlapSpans(int source_first, int source_count, double source_origin_m,
                                   double source_resolution_m, double window_origin_m,
                                   double window_resolution_m, int window_cells) {
  std::vector<CellSpan> spans(source_count);
  for (int i = 0; i < source_count; ++i) {
    const double lo_m = source_origin_m + (source_first + i) * source_resolution_m;
    const double lo = (lo_m - window_origin_m) / window_resolution_m;
    const double hi = (lo_m + source_resolution_m - window_origin_m) / window_resolution_m;
    spans[i].first = std::max(0, static_cast<int>(std::floor(lo + kBoundaryEpsilonCells)));
    spans[i].last =
        std::min(window_cells - 1, static_cast<int>(std::ceil(hi - kBoundaryEpsilonCells)) - 1);
  }
  return spans;
}

}  // namespace

void LocalObstaclesOptions::Validate() const {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
    ThrowBadOption("resolution_m", resolution_m, "must be finite and > 0");
  }
  if (!(window_m >= 2.0 * resolution_m) || !std::isfinite(window_m)) {
    ThrowBadOption("window_m", window_m, "must be finite and at least two cells");
  }
  if (window_m / resolution_m > 4096.0) {
    ThrowBadOption("window_m", window_m, "must be at most 4096 cells");
  }
  if (occupied_threshold < 1 || occupied_threshold > 100) {
    ThrowBadOption("occupied_threshold", occupied_threshold, "must be in 1..100");
  }
}

LocalObstacles::LocalObstacles(const OccupancyGrid& map, const std::vector<Point2d>& scan_points_m,
                               const Pose2d& robot_in_map, const LocalObstaclesOptions& options)
    : options_(options) {
  try {
    options_.Validate();
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "LocalObstacles: %s\n", error.what());
    std::abort();
  }
  const double res = options_.resolution_m;
  const int n = std::max(2, static_cast<int>(std::lround(options_.window_m / res)));
  size_cells_ = n;

  // Same resolution: align the window to the map's cells so each map cell is
  // exactly one window cell (no smearing); otherwise to multiples of res.
  const bool aligned = !map.empty() && std::abs(map.resolution_m() - res) < 1e-9 * res;
  const Point2d grid_origin_m = aligned ? map.origin_m() : Point2d{0.0, 0.0};
  const double first_col = std::floor((robot_in_map.x_m - grid_origin_m.x_m) / res) - n / 2;
  const double first_row = std::floor((robot_in_map.y_m - grid_origin_m.y_m) / res) - n / 2;
  origin_m_ = {grid_origin_m.x_m + first_col * res, grid_origin_m.y_m + first_row * res};

  // distanceTransform measures to the nearest zero pixel: obstacles are 0.
  cv::Mat free_mask(n, n, CV_8U, cv::Scalar(255));
  bool any_obstacle = false;

  if (!map.empty()) {
    const double map_res = map.resolution_m();
    const Point2d map_origin = map.origin_m();
    // Map cells that may overlap the window.
    const int col_lo =
        std::max(0, static_cast<int>(std::floor((origin_m_.x_m - map_origin.x_m) / map_res)) - 1);
    const int col_hi = std::min(
        map.width_cells() - 1,
        static_cast<int>(std::floor((origin_m_.x_m + n * res - map_origin.x_m) / map_res)) + 1);
    const int row_lo =
        std::max(0, static_cast<int>(std::floor((origin_m_.y_m - map_origin.y_m) / map_res)) - 1);
    const int row_hi = std::min(
        map.height_cells() - 1,
        static_cast<int>(std::floor((origin_m_.y_m + n * res - map_origin.y_m) / map_res)) + 1);
    if (col_lo <= col_hi && row_lo <= row_hi) {
      const std::vector<CellSpan> col_spans =
          OverlapSpans(col_lo, col_hi - col_lo + 1, map_origin.x_m, map_res, origin_m_.x_m, res, n);
      const std::vector<CellSpan> row_spans =
          OverlapSpans(row_lo, row_hi - row_lo + 1, map_origin.y_m, map_res, origin_m_.y_m, res, n);
      const std::vector<int8_t>& cells = map.cells();
      const int threshold = options_.occupied_threshold;
      for (int row = row_lo; row <= row_hi; ++row) {
        const CellSpan& rows = row_spans[row - row_lo];
        if (rows.first > rows.last) continue;
        const int8_t* map_row = cells.data() + static_cast<std::size_t>(row) * map.width_cells();
        for (int col = col_lo; col <= col_hi; ++col) {
          if (map_row[col] < threshold) continue;  // unknown (-1) is not an obstacle
          const CellSpan& cols = col_spans[col - col_lo];
          for (int r = rows.first; r <= rows.last; ++r) {
            uint8_t* out = free_mask.ptr<uint8_t>(r);
            for (int c = cols.first; c <= cols.last; ++c) {
              out[c] = 0;
              any_obstacle = true;
            }
          }
        }
      }
    }
  }

  for (const Point2d& point : scan_points_m) {
    // Cells counted from the fixed grid origin, not the window's: a point on a
    // cell boundary then lands in the same cell wherever the window sits.
    const double col = std::floor((point.x_m - grid_origin_m.x_m) / res) - first_col;
    const double row = std::floor((point.y_m - grid_origin_m.y_m) / res) - first_row;
    if (!(col >= 0.0 && row >= 0.0 && col < n && row < n)) continue;  // also drops NaN
    free_mask.at<uint8_t>(static_cast<int>(row), static_cast<int>(col)) = 0;
    any_obstacle = true;
  }

  distance_m_.resize(static_cast<std::size_t>(n) * n);
  if (!any_obstacle) {
    // OpenCV returns a large finite sentinel here; any value beyond the window will do.
    std::fill(distance_m_.begin(), distance_m_.end(), static_cast<float>(2.0 * n * res));
    return;
  }
  cv::Mat distance_cells;
  cv::distanceTransform(free_mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  const float scale = static_cast<float>(res);
  for (int r = 0; r < n; ++r) {
    const float* in = distance_cells.ptr<float>(r);
    float* out = distance_m_.data() + static_cast<std::size_t>(r) * n;
    for (int c = 0; c < n; ++c) out[c] = in[c] * scale;
  }
}

double LocalObstacles::ClearanceM(const Point2d& point_m) const {
  if (size_cells_ == 0) return 0.0;
  const double res = options_.resolution_m;
  // Continuous coordinates in which cell centres sit on integers.
  const double gx = (point_m.x_m - origin_m_.x_m) / res - 0.5;
  const double gy = (point_m.y_m - origin_m_.y_m) / res - 0.5;
  const double last = size_cells_ - 1;
  if (!(gx >= 0.0 && gy >= 0.0 && gx <= last && gy <= last)) return 0.0;  // also NaN
  const int c = std::min(static_cast<int>(gx), size_cells_ - 2);
  const int r = std::min(static_cast<int>(gy), size_cells_ - 2);
  const double fx = gx - c;
  const double fy = gy - r;
  const float* row0 = distance_m_.data() + static_cast<std::size_t>(r) * size_cells_ + c;
  const float* row1 = row0 + size_cells_;
  const double bottom = row0[0] + fx * (row0[1] - row0[0]);
  const double top = row1[0] + fx * (row1[1] - row1[0]);
  const double centre_distance_m = bottom + fy * (top - bottom);
  return std::max(0.0, centre_distance_m - 0.5 * res);
}

}  // namespace aslam
