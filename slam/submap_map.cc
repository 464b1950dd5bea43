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
    // Closing a submap moves its log-odds into the sum: no cell's total changes.
    if (!submaps_.empty()) Fuse(submaps_.back(), +1);
    submaps_.emplace_back(options_);
    scans_in_open_submap_ = 0;
  }
  if (const std::optional<CellBox> box = submaps_.back().InsertScan(base_in_map, scan)) {
    MarkChanged(*box);
  }
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
  // A grid's extent only grows, so the new one holds every cell the old scans touched too.
  const OccupancyMapper::Extent e = submap.extent();
  if (e.width > 0 && e.height > 0) {
    MarkChanged(
        {e.origin_col, e.origin_row, e.origin_col + e.width - 1, e.origin_row + e.height - 1});
  }
}

void SubmapMap::MarkChanged(const CellBox& box) {
  if (!changed_) {
    changed_ = box;
    return;
  }
  changed_->min_col = std::min(changed_->min_col, box.min_col);
  changed_->min_row = std::min(changed_->min_row, box.min_row);
  changed_->max_col = std::max(changed_->max_col, box.max_col);
  changed_->max_row = std::max(changed_->max_row, box.max_row);
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

void SubmapMap::RelayoutRendered(const OccupancyMapper::Extent& extent) {
  const double res = options_.resolution_m;
  OccupancyGrid grid(extent.width, extent.height, res,
                     {extent.origin_col * res, extent.origin_row * res});
  const OccupancyMapper::Extent& old = rendered_extent_;
  // Both extents hold whole rows of global cells: copy the old one's rows into place.
  for (int row = 0; row < old.height; ++row) {
    const int to_row = row + old.origin_row - extent.origin_row;
    std::copy_n(rendered_.cells().begin() + static_cast<std::size_t>(row) * old.width, old.width,
                grid.mutable_cells().begin() + static_cast<std::size_t>(to_row) * extent.width +
                    (old.origin_col - extent.origin_col));
  }
  rendered_ = std::move(grid);
  rendered_extent_ = extent;
}

OccupancyGrid SubmapMap::Render() {
  if (empty()) return OccupancyGrid();
  // The sum's extent and the open submap's, together (and the last render's: grids only grow).
  const OccupancyMapper& open = submaps_.back();
  const OccupancyMapper::Extent all = Covering(Covering(fusion_, open.extent()), rendered_extent_);
  const OccupancyMapper::Extent& was = rendered_extent_;
  if (all.origin_col != was.origin_col || all.origin_row != was.origin_row ||
      all.width != was.width || all.height != was.height) {
    RelayoutRendered(all);
  }
  if (!changed_) return rendered_;
  const int min_col = std::max(changed_->min_col, all.origin_col);
  const int max_col = std::min(changed_->max_col, all.origin_col + all.width - 1);
  const int min_row = std::max(changed_->min_row, all.origin_row);
  const int max_row = std::min(changed_->max_row, all.origin_row + all.height - 1);
  changed_.reset();
  if (min_col > max_col || min_row > max_row) return rendered_;
  // The box's summed log-odds and whether any submap observed each cell, as in one render.
  const int box_width = max_col - min_col + 1;
  const std::size_t box_cells = static_cast<std::size_t>(box_width) * (max_row - min_row + 1);
  sum_scratch_.assign(box_cells, 0);
  observed_scratch_.assign(box_cells, 0);
  auto box_index = [&](int col, int row) {
    return static_cast<std::size_t>(row - min_row) * box_width + (col - min_col);
  };
  const int fusion_min_col = std::max(min_col, fusion_.origin_col);
  const int fusion_max_col = std::min(max_col, fusion_.origin_col + fusion_.width - 1);
  for (int row = std::max(min_row, fusion_.origin_row);
       row <= std::min(max_row, fusion_.origin_row + fusion_.height - 1); ++row) {
    const std::size_t from = static_cast<std::size_t>(row - fusion_.origin_row) * fusion_.width;
    for (int col = fusion_min_col; col <= fusion_max_col; ++col) {
      const std::size_t f = from + (col - fusion_.origin_col);
      sum_scratch_[box_index(col, row)] = sum_milli_[f];
      observed_scratch_[box_index(col, row)] = observers_[f] > 0;
    }
  }
  open.ForEachObservedIn({min_col, min_row, max_col, max_row},
                         [&](int col, int row, float log_odds) {
                           sum_scratch_[box_index(col, row)] += ToMilli(log_odds);
                           observed_scratch_[box_index(col, row)] = 1;
                         });
  const LogOddsRenderer render(options_);
  std::vector<int8_t>& cells = rendered_.mutable_cells();
  for (int row = min_row; row <= max_row; ++row) {
    int8_t* out = cells.data() + static_cast<std::size_t>(row - all.origin_row) * all.width +
                  (min_col - all.origin_col);
    const std::size_t in = box_index(min_col, row);
    for (int c = 0; c < box_width; ++c) {
      out[c] = observed_scratch_[in + c] ? render(static_cast<float>(sum_scratch_[in + c] / kMilli))
                                         : OccupancyGrid::kUnknown;
    }
  }
  return rendered_;
}

}  // namespace aslam
