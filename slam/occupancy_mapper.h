#pragma once

// Log-odds occupancy mapping: every scan's beams are ray cast from its
// keyframe pose, cells along a beam get a miss, the end cell a hit. The grid
// grows to cover whatever is inserted. Rendered in the ROS convention.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"

namespace aslam {

struct OccupancyMapperOptions {
  double resolution_m = 0.05;
  double log_odds_hit = 0.85;   // added at a beam's end cell
  double log_odds_miss = -0.4;  // added to every cell the beam passes
  double log_odds_min = -2.0;   // clamps keep the map able to change
  double log_odds_max = 3.5;
  // A beam with no return clears this far (0: no-return beams are ignored).
  double no_return_clear_m = 0.0;
  double growth_margin_m = 2.0;  // extra border added whenever the grid grows
  // Rendering: p <= free_threshold reads 0 (free), p >= occupied_threshold 100
  // (occupied), anything between round(100 p), so consumers see clean free space.
  double free_threshold =
      0.45;  // one miss (p = 0.40) already reads free: a first scan shows free space
  double occupied_threshold = 0.65;
};

// Global cells [min, max] (both included), in floor(map / resolution) indices.
struct CellBox {
  int min_col = 0;
  int min_row = 0;
  int max_col = -1;
  int max_row = -1;
  // The smallest box holding both.
  CellBox Union(const CellBox& other) const {
    return {std::min(min_col, other.min_col), std::min(min_row, other.min_row),
            std::max(max_col, other.max_col), std::max(max_row, other.max_row)};
  }
  bool Intersects(const CellBox& other) const {
    return min_col <= other.max_col && other.min_col <= max_col && min_row <= other.max_row &&
           other.min_row <= max_row;
  }
};

class OccupancyMapper {
 public:
  // Throws std::invalid_argument naming the option on a bad value.
  explicit OccupancyMapper(OccupancyMapperOptions options);

  // Forgets every observation but keeps the grid's extent, so re-inserting
  // all keyframes after a loop closure does not regrow (and recopy) the grid.
  void Clear();
  // Inserts one scan taken with the base at `base_in_map`. Each cell changes
  // at most once per scan and a hit beats a miss, so beams grazing a wall in
  // the same scan cannot erase it. Range 0 is a beam without a return (see
  // options); NaN, inf, negative, out-of-[range_min, range_max] and > 100 m
  // beams are skipped. Aborts on a non-finite pose (a bug upstream).
  // Returns the cells the scan may have changed (none: no usable beam).
  std::optional<CellBox> InsertScan(const Pose2d& base_in_map, const LidarScan& scan);
  // The cells InsertScan(base_in_map, scan) would change, without changing any.
  std::optional<CellBox> ScanFootprint(const Pose2d& base_in_map, const LidarScan& scan);

  // A scan to re-insert, with its footprint at that pose.
  struct PosedScan {
    Pose2d base_in_map;
    const LidarScan* scan = nullptr;
    CellBox footprint;
  };
  // Re-renders the cells of `region` only: forgets what they observed, then
  // re-inserts `scans` in order, changing nothing outside the region. Given
  // every scan of the map whose footprint meets the region, in the order of
  // insertion, the region ends as a fresh insertion of all of them would leave
  // it (log-odds are clamped in insertion order, so order matters).
  void RerenderRegion(const std::vector<CellBox>& region, const std::vector<PosedScan>& scans);

  // How many never-observed cells inserting `scan` at `base_in_map` would observe (a
  // cell crossed by several beams counts once per beam). Changes nothing.
  int CountRevealedCells(const Pose2d& base_in_map, const LidarScan& scan) const;

  // -1 never observed, else round(100 * p_occupied). Empty grid when empty().
  OccupancyGrid Render() const;
  // True until a scan observes a cell (again true after Clear()).
  bool empty() const;

  const OccupancyMapperOptions& options() const { return options_; }

 private:
  struct BeamEnd {
    int col;  // grid cell, valid after GrowToCover
    int row;
    bool hit;
  };

  // Grows the grid so the global cells [min, max] fit, with growth_margin_m to spare.
  void GrowToCover(int min_col, int min_row, int max_col, int max_row);
  // Beam end cells (global indices) into *ends and the sensor's cell, and their box;
  // none when no beam is usable. Aborts on a non-finite pose.
  std::optional<CellBox> BeamEndCells(const Pose2d& base_in_map, const LidarScan& scan,
                                      std::vector<BeamEnd>* ends, int* sensor_col,
                                      int* sensor_row) const;
  // Pass 1 of an insertion: BeamEndCells into beam_ends_, sensor_col_ and sensor_row_.
  std::optional<CellBox> ComputeBeamEnds(const Pose2d& base_in_map, const LidarScan& scan);
  // The insertion; with kInRegionOnly, cells outside region_mask_ are left alone.
  template <bool kInRegionOnly>
  std::optional<CellBox> Insert(const Pose2d& base_in_map, const LidarScan& scan);

  OccupancyMapperOptions options_;
  int width_cells_ = 0;
  int height_cells_ = 0;
  // Global cell index (floor(world / resolution)) of grid cell (0, 0): an
  // integer, so cells never shift when the grid grows.
  int origin_col_ = 0;
  int origin_row_ = 0;
  struct Cell {
    float log_odds;  // NaN = never observed
    uint32_t stamp;  // number of the scan that last changed the cell
  };
  std::vector<Cell> cells_;  // row-major; side by side, one cache line per visit
  uint32_t scan_stamp_ = 0;
  bool empty_ = true;
  std::vector<BeamEnd> beam_ends_;     // scratch for InsertScan
  std::vector<uint8_t> region_mask_;   // RerenderRegion's cells, one per grid cell
  std::vector<CellBox> region_boxes_;  // ...and the region's boxes the current scan meets
  int sensor_col_ = 0;                 // ComputeBeamEnds' sensor cell (global)
  int sensor_row_ = 0;
};

}  // namespace aslam
