#pragma once

// The SLAM map as submaps (Cartographer's design on our pose graph): each run of
// options.submap_keyframes consecutive mapped keyframes is its own clamped log-odds grid
// (an OccupancyMapper), and the map is the sum of their log-odds. A sum does not depend on
// order, so after a loop closure only the submaps whose keyframes moved are rebuilt: each is
// taken out of the sum, re-rendered from its own keyframes, and put back. The cost of a
// closure is the moved keyframes', not the map's.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"
#include "slam/occupancy_mapper.h"

namespace aslam {

class SubmapMap {
 public:
  // Throws std::invalid_argument naming the option on a bad value.
  explicit SubmapMap(OccupancyMapperOptions options);

  // Inserts a scan into the newest submap (a new one once it holds submap_keyframes scans)
  // and returns that submap's index. Bad beams and poses as OccupancyMapper::InsertScan.
  int InsertScan(const Pose2d& base_in_map, const LidarScan& scan);

  struct PosedScan {
    Pose2d base_in_map;
    const LidarScan* scan = nullptr;
  };
  // Rebuilds submap `index` from `scans`: all of its scans, in insertion order, at their
  // current poses. Throws std::out_of_range for an unknown index.
  void RerenderSubmap(int index, const std::vector<PosedScan>& scans);

  // How many cells no submap has observed that inserting `scan` at `base_in_map` would
  // observe (a cell crossed by several beams counts once per beam). Changes nothing.
  int CountRevealedCells(const Pose2d& base_in_map, const LidarScan& scan) const;

  // The fused map: -1 where no submap observed a cell, else round(100 * p_occupied) of the
  // summed log-odds, thresholded as OccupancyMapper::Render. Empty grid when empty().
  // Renders only the cells changed since the last call; the rest comes from that call's grid.
  OccupancyGrid Render();
  bool empty() const;
  int num_submaps() const { return static_cast<int>(submaps_.size()); }

 private:
  // Adds (sign +1) or removes (-1) a closed submap's log-odds from the sum.
  void Fuse(const OccupancyMapper& submap, int sign);
  void GrowFusionToCover(const OccupancyMapper::Extent& extent);
  bool FusionObserved(int col, int row) const;
  void MarkChanged(const CellBox& box);
  // The last render laid out over `extent` (the cells outside what it covered unknown).
  void RelayoutRendered(const OccupancyMapper::Extent& extent);

  OccupancyMapperOptions options_;
  std::vector<OccupancyMapper> submaps_;  // the last one is open: not in the sum yet
  int scans_in_open_submap_ = 0;
  // The closed submaps' sum in fixed point (exact, so a submap comes out as it went in).
  OccupancyMapper::Extent fusion_;
  std::vector<int32_t> sum_milli_;
  std::vector<uint16_t> observers_;  // closed submaps that observed the cell
  // The last Render()'s grid, its extent, and the cells changed since (global indices).
  OccupancyGrid rendered_;
  OccupancyMapper::Extent rendered_extent_;
  std::optional<CellBox> changed_;
  std::vector<int32_t> sum_scratch_;  // Render()'s, kept to spare the allocations
  std::vector<uint8_t> observed_scratch_;
};

}  // namespace aslam
