#include "slam/submap_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace aslam {
namespace {

// Log-odds in the sum are integers of this many per unit: exact to add and take out.
constexpr double kMilli = 1000.0;

int32_t ToMilli(float log_odds) { return static_cast<int32_t>(std::lround(log_odds * kMilli)); }

// The smallest extent holding both; an empty one (width 0) holds nothing.
OccupancyMapper::Extent Covering(const OccupancyMapper::Extent& a,
                                 const OccupancyMapper::Extent& b) {
  if (a.width == 0) return b;
  if (b.width == 0) return a;
  OccupancyMapper::Extent both;
  both.origin_col = std::min(a.origin_col, b.origin_col);
  both.origin_row = std::min(a.origin_row, b.origin_row);
  both.width = std::max(a.origin_col + a.width, b.origin_col + b.width) - both.origin_col;
  both.height = std::max(a.origin_row + a.height, b.origin_row + b.height) - both.origin_row;
  return both;
}

}  // namespace

SubmapMap::SubmapMap(OccupancyMapperOptions options) : options_(std::move(options)) {
  OccupancyMapper check(options_);  // throws std::invalid_argument naming the option
}

bool SubmapMap::empty() const {
  for (const OccupancyMapper& submap : submaps_) {
    if (!submap.empty()) return false;
  }
  return true;
}

int SubmapMap::InsertScan(const Pose2d& base_in_map, const LidarScan& scan) {
  if (submaps_.empty() || scans_in_open_submap_ >= options_.submap_keyframes) {
    if (!submaps_.empty()) Fuse(submaps_.back(), +1);
    submaps_.emplace_back(options_);
    scans_in_open_submap_ = 0;
  }
  submaps_.back().InsertScan(base_in_map, scan);
  ++scans_in_open_submap_;
  return static_cast<int>(submaps_.size()) - 1;
}

void SubmapMap::RerenderSubmap(int index, const std::vector<PosedScan>& scans) {
  if (index < 0 || index >= num_submaps()) {
    throw std::out_of_range("SubmapMap: no submap " + std::to_string(index));
  }
  OccupancyMapper& submap = submaps_[index];
  const bool closed = index + 1 < num_submaps();
  if (closed) Fuse(submap, -1);
  submap.Clear();
  for (const PosedScan& posed : scans) submap.InsertScan(posed.base_in_map, *posed.scan);
  if (closed) Fuse(submap, +1);
}

void SubmapMap::GrowFusionToCover(const OccupancyMapper::Extent& e) {
  OccupancyMapper::Extent& f = fusion_;
  if (e.width == 0 || e.height == 0) return;
  if (f.width > 0 && e.origin_col >= f.origin_col && e.origin_row >= f.origin_row &&
      e.origin_col + e.width <= f.origin_col + f.width &&
      e.origin_row + e.height <= f.origin_row + f.height) {
    return;
  }
  const OccupancyMapper::Extent grown = Covering(f, e);
  const std::size_t cells = static_cast<std::size_t>(grown.width) * grown.height;
  std::vector<int32_t> sum(cells, 0);
  std::vector<uint16_t> observers(cells, 0);
  for (int row = 0; row < f.height; ++row) {
    const std::size_t from = static_cast<std::size_t>(row) * f.width;
    const std::size_t to =
        static_cast<std::size_t>(row + f.origin_row - grown.origin_row) * grown.width +
        (f.origin_col - grown.origin_col);
    std::copy_n(sum_milli_.begin() + from, f.width, sum.begin() + to);
    std::copy_n(observers_.begin() + from, f.width, observers.begin() + to);
  }
  sum_milli_ = std::move(sum);
  observers_ = std::move(observers);
  fusion_ = grown;
}

void SubmapMap::Fuse(const OccupancyMapper& submap, int sign) {
  if (sign > 0) GrowFusionToCover(submap.extent());
  const OccupancyMapper::Extent& f = fusion_;
  submap.ForEachObserved([&](int col, int row, float log_odds) {
    const std::size_t i =
        static_cast<std::size_t>(row - f.origin_row) * f.width + (col - f.origin_col);
    sum_milli_[i] += sign * ToMilli(log_odds);
    observers_[i] = static_cast<uint16_t>(observers_[i] + sign);
  });
}

bool SubmapMap::FusionObserved(int col, int row) const {
  const int c = col - fusion_.origin_col, r = row - fusion_.origin_row;
  if (c < 0 || r < 0 || c >= fusion_.width || r >= fusion_.height) return false;
  return observers_[static_cast<std::size_t>(r) * fusion_.width + c] > 0;
}

int SubmapMap::CountRevealedCells(const Pose2d& base_in_map, const LidarScan& scan) const {
  if (submaps_.empty()) {
    return OccupancyMapper(options_).CountRevealedCells(base_in_map, scan);
  }
  const OccupancyMapper& open = submaps_.back();
  return open.CountBeamCells(base_in_map, scan, [&](int col, int row) {
    return std::isnan(open.LogOddsAt(col, row)) && !FusionObserved(col, row);
  });
}

OccupancyGrid SubmapMap::Render() const {
  if (empty()) return OccupancyGrid();
  // The sum's extent and the open submap's, together.
  const OccupancyMapper::Extent open = submaps_.back().extent();
  const OccupancyMapper::Extent all = Covering(fusion_, open);
  const double res = options_.resolution_m;
  OccupancyGrid grid(all.width, all.height, res, {all.origin_col * res, all.origin_row * res});
  std::vector<int32_t> sum(static_cast<std::size_t>(all.width) * all.height, 0);
  std::vector<uint8_t> observed(sum.size(), 0);
  for (int row = 0; row < fusion_.height; ++row) {
    const std::size_t from = static_cast<std::size_t>(row) * fusion_.width;
    const std::size_t to =
        static_cast<std::size_t>(row + fusion_.origin_row - all.origin_row) * all.width +
        (fusion_.origin_col - all.origin_col);
    for (int col = 0; col < fusion_.width; ++col) {
      sum[to + col] = sum_milli_[from + col];
      observed[to + col] = observers_[from + col] > 0;
    }
  }
  submaps_.back().ForEachObserved([&](int col, int row, float log_odds) {
    const std::size_t i =
        static_cast<std::size_t>(row - all.origin_row) * all.width + (col - all.origin_col);
    sum[i] += ToMilli(log_odds);
    observed[i] = 1;
  });
  const LogOddsRenderer render(options_);
  std::vector<int8_t>& cells = grid.mutable_cells();
  for (std::size_t i = 0; i < sum.size(); ++i) {
    if (observed[i]) cells[i] = render(static_cast<float>(sum[i] / kMilli));
  }
  return grid;
}

}  // namespace aslam
