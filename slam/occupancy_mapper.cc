#include "slam/occupancy_mapper.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace aslam {
namespace {

constexpr float kUnobserved = std::numeric_limits<float>::quiet_NaN();
// Longer returns are treated as bad data: one spurious far return would
// otherwise grow the grid (8 bytes a cell) to gigabytes.
constexpr double kMaxBeamLengthM = 100.0;

void Require(bool ok, const char* key, double value) {
  if (!ok) {
    throw std::invalid_argument("OccupancyMapperOptions: bad " + std::string(key) + " = " +
                                std::to_string(value));
  }
}

}  // namespace

OccupancyMapper::OccupancyMapper(OccupancyMapperOptions options) : options_(std::move(options)) {
  const OccupancyMapperOptions& o = options_;
  Require(o.resolution_m > 0.0 && std::isfinite(o.resolution_m), "resolution_m", o.resolution_m);
  Require(o.log_odds_hit > 0.0, "log_odds_hit", o.log_odds_hit);
  Require(o.log_odds_miss < 0.0, "log_odds_miss", o.log_odds_miss);
  Require(o.log_odds_min < 0.0, "log_odds_min", o.log_odds_min);
  Require(o.log_odds_max > 0.0 && std::isfinite(o.log_odds_max), "log_odds_max", o.log_odds_max);
  Require(std::isfinite(o.log_odds_min), "log_odds_min", o.log_odds_min);
  Require(o.no_return_clear_m >= 0.0 && o.no_return_clear_m <= kMaxBeamLengthM, "no_return_clear_m",
          o.no_return_clear_m);
  Require(o.growth_margin_m >= 0.0 && o.growth_margin_m <= kMaxBeamLengthM, "growth_margin_m",
          o.growth_margin_m);
  Require(o.free_threshold > 0.0 && o.free_threshold < 0.5, "free_threshold", o.free_threshold);
  Require(o.occupied_threshold > 0.5 && o.occupied_threshold < 1.0, "occupied_threshold",
          o.occupied_threshold);
  Require(o.submap_keyframes >= 1, "submap_keyframes", o.submap_keyframes);
}

void OccupancyMapper::Clear() {
  for (Cell& cell : cells_) cell.log_odds = kUnobserved;
  empty_ = true;
}

bool OccupancyMapper::empty() const { return empty_; }

void OccupancyMapper::GrowToCover(int min_col, int min_row, int max_col, int max_row) {
  const int margin = static_cast<int>(std::ceil(options_.growth_margin_m / options_.resolution_m));
  int new_min_col, new_min_row, new_max_col, new_max_row;
  if (cells_.empty()) {
    new_min_col = min_col - margin;
    new_min_row = min_row - margin;
    new_max_col = max_col + margin;
    new_max_row = max_row + margin;
  } else {
    const int old_max_col = origin_col_ + width_cells_ - 1;
    const int old_max_row = origin_row_ + height_cells_ - 1;
    if (min_col >= origin_col_ && min_row >= origin_row_ && max_col <= old_max_col &&
        max_row <= old_max_row) {
      return;
    }
    // Only the sides that overflow move, by the overflow plus the margin.
    new_min_col = min_col < origin_col_ ? min_col - margin : origin_col_;
    new_min_row = min_row < origin_row_ ? min_row - margin : origin_row_;
    new_max_col = max_col > old_max_col ? max_col + margin : old_max_col;
    new_max_row = max_row > old_max_row ? max_row + margin : old_max_row;
  }
  const int new_width = new_max_col - new_min_col + 1;
  const int new_height = new_max_row - new_min_row + 1;
  // Stamps only matter within one scan, and growth happens before its updates.
  std::vector<Cell> cells(static_cast<std::size_t>(new_width) * new_height, Cell{kUnobserved, 0});
  for (int row = 0; row < height_cells_; ++row) {
    const auto src = cells_.begin() + static_cast<std::size_t>(row) * width_cells_;
    const std::size_t dst = static_cast<std::size_t>(row + origin_row_ - new_min_row) * new_width +
                            (origin_col_ - new_min_col);
    std::copy(src, src + width_cells_, cells.begin() + dst);
  }
  cells_ = std::move(cells);
  width_cells_ = new_width;
  height_cells_ = new_height;
  origin_col_ = new_min_col;
  origin_row_ = new_min_row;
}

std::optional<CellBox> OccupancyMapper::BeamEndCells(const Pose2d& base_in_map,
                                                     const LidarScan& scan,
                                                     std::vector<BeamEnd>* ends, int* sensor_col,
                                                     int* sensor_row) const {
  const Pose2d sensor = base_in_map.Compose(scan.sensor_pose);
  if (!std::isfinite(sensor.x_m) || !std::isfinite(sensor.y_m) || !std::isfinite(sensor.yaw_rad) ||
      std::abs(sensor.x_m) > 1e6 || std::abs(sensor.y_m) > 1e6) {
    std::fprintf(stderr, "OccupancyMapper: sensor pose (%g, %g, %g) is not a usable pose\n",
                 sensor.x_m, sensor.y_m, sensor.yaw_rad);
    std::abort();  // the front end hands us optimized poses: garbage here is a bug
  }
  const double inv_res = 1.0 / options_.resolution_m;
  *sensor_col = static_cast<int>(std::floor(sensor.x_m * inv_res));
  *sensor_row = static_cast<int>(std::floor(sensor.y_m * inv_res));
  ends->clear();
  CellBox box{*sensor_col, *sensor_row, *sensor_col, *sensor_row};
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    const float range = scan.range_m[i];
    double length_m;
    bool hit;
    if (range == 0.0f) {  // no return
      if (options_.no_return_clear_m <= 0.0) continue;
      length_m = options_.no_return_clear_m;
      hit = false;
    } else if (scan.IsValidReturn(i) && range <= kMaxBeamLengthM) {
      length_m = range;
      hit = true;
    } else {
      continue;
    }
    const double angle = sensor.yaw_rad + scan.BeamAngle(i);
    const int col =
        static_cast<int>(std::floor((sensor.x_m + length_m * std::cos(angle)) * inv_res));
    const int row =
        static_cast<int>(std::floor((sensor.y_m + length_m * std::sin(angle)) * inv_res));
    ends->push_back({col, row, hit});
    box.min_col = std::min(box.min_col, col);
    box.max_col = std::max(box.max_col, col);
    box.min_row = std::min(box.min_row, row);
    box.max_row = std::max(box.max_row, row);
  }
  if (ends->empty()) return std::nullopt;
  return box;
}

std::optional<CellBox> OccupancyMapper::InsertScan(const Pose2d& base_in_map,
                                                   const LidarScan& scan) {
  // Pass 1: beam end cells (global indices) and their bounding box.
  int sensor_col = 0, sensor_row = 0;
  const std::optional<CellBox> footprint =
      BeamEndCells(base_in_map, scan, &beam_ends_, &sensor_col, &sensor_row);
  if (!footprint) return std::nullopt;

  // One growth per scan; every cell touched below is then inside the grid.
  GrowToCover(footprint->min_col, footprint->min_row, footprint->max_col, footprint->max_row);
  empty_ = false;
  if (++scan_stamp_ == 0) {  // wrapped: old stamps could collide
    for (Cell& cell : cells_) cell.stamp = 0;
    scan_stamp_ = 1;
  }
  const uint32_t stamp = scan_stamp_;
  const float hit_lo = static_cast<float>(options_.log_odds_hit);
  const float miss_lo = static_cast<float>(options_.log_odds_miss);
  const float lo_min = static_cast<float>(options_.log_odds_min);
  const float lo_max = static_cast<float>(options_.log_odds_max);
  Cell* const grid = cells_.data();
  const int width = width_cells_;

  auto update = [&](std::ptrdiff_t index, float delta) {
    Cell& cell = grid[index];
    if (cell.stamp == stamp) return;
    cell.stamp = stamp;
    const float value = std::isnan(cell.log_odds) ? 0.0f : cell.log_odds;
    cell.log_odds = std::clamp(value + delta, lo_min, lo_max);
  };
  // Pass 2: hits first, so a miss of another beam in this scan cannot touch them.
  for (BeamEnd& end : beam_ends_) {
    end.col -= origin_col_;
    end.row -= origin_row_;
    if (end.hit) update(static_cast<std::ptrdiff_t>(end.row) * width + end.col, hit_lo);
  }

  // Pass 3: misses along each beam, the end cell excluded for a hit and
  // included for a no-return beam. Bresenham on cell indices, written as one
  // step along the major axis per cell plus a carry on the minor axis, so the
  // stepping has no data-dependent branch.
  const int start_col = sensor_col - origin_col_;
  const int start_row = sensor_row - origin_row_;
  const std::ptrdiff_t start_index = static_cast<std::ptrdiff_t>(start_row) * width + start_col;
  for (const BeamEnd& end : beam_ends_) {
    const int dx = std::abs(end.col - start_col);
    const int dy = std::abs(end.row - start_row);
    const std::ptrdiff_t step_x = end.col > start_col ? 1 : -1;
    const std::ptrdiff_t step_y = end.row > start_row ? width : -width;
    const bool x_major = dx >= dy;
    const int d_major = x_major ? dx : dy;  // cells after the start cell, up to the end cell
    const int d_minor = x_major ? dy : dx;
    const std::ptrdiff_t major_step = x_major ? step_x : step_y;
    const std::ptrdiff_t minor_step = x_major ? step_y : step_x;
    std::ptrdiff_t index = start_index;
    int err = d_major / 2;  // midpoint rounding of the minor coordinate
    for (int k = 0; k < d_major; ++k) {
      update(index, miss_lo);
      err += d_minor;
      const bool carry = err >= d_major;
      err -= carry ? d_major : 0;
      index += major_step + (carry ? minor_step : 0);
    }
    if (!end.hit) update(index, miss_lo);
  }
  return footprint;
}

int OccupancyMapper::CountRevealedCells(const Pose2d& base_in_map, const LidarScan& scan) const {
  return CountBeamCells(base_in_map, scan,
                        [this](int col, int row) { return std::isnan(LogOddsAt(col, row)); });
}

float OccupancyMapper::LogOddsAt(int col, int row) const {
  const int c = col - origin_col_, r = row - origin_row_;
  if (c < 0 || r < 0 || c >= width_cells_ || r >= height_cells_) return kUnobserved;
  return cells_[static_cast<std::size_t>(r) * width_cells_ + c].log_odds;
}

LogOddsRenderer::LogOddsRenderer(const OccupancyMapperOptions& options)
    : free_threshold_(options.free_threshold),
      occupied_threshold_(options.occupied_threshold),
      free_logit_(std::log(free_threshold_ / (1.0 - free_threshold_))),
      occupied_logit_(std::log(occupied_threshold_ / (1.0 - occupied_threshold_))) {}

int8_t LogOddsRenderer::RenderBetween(float log_odds) const {
  const double p = 1.0 / (1.0 + std::exp(-static_cast<double>(log_odds)));
  return p <= free_threshold_       ? OccupancyGrid::kFree
         : p >= occupied_threshold_ ? OccupancyGrid::kOccupied
                                    : static_cast<int8_t>(std::lround(100.0 * p));
}

OccupancyGrid OccupancyMapper::Render() const {
  if (empty_) return OccupancyGrid();
  const double res = options_.resolution_m;
  OccupancyGrid grid(width_cells_, height_cells_, res, {origin_col_ * res, origin_row_ * res});
  std::vector<int8_t>& cells = grid.mutable_cells();
  const LogOddsRenderer render(options_);
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    const float value = cells_[i].log_odds;
    if (!std::isnan(value)) cells[i] = render(value);  // else stays kUnknown
  }
  return grid;
}

}  // namespace aslam
