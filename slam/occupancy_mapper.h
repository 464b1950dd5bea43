#pragma once

// Log-odds occupancy mapping: every scan's beams are ray cast from its
// keyframe pose, cells along a beam get a miss, the end cell a hit. The grid
// grows to cover whatever is inserted. Rendered in the ROS convention.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
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
  // SubmapMap: consecutive mapped keyframes per submap (its own clamped grid; see submap_map.h).
  int submap_keyframes = 20;
};

// Log-odds to the ROS convention with the options' thresholds (see free_threshold).
class LogOddsRenderer {
 public:
  explicit LogOddsRenderer(const OccupancyMapperOptions& options);
  // Inline: called once per cell of every rendered map.
  int8_t operator()(float log_odds) const {
    constexpr double kMargin = 1e-6;
    if (log_odds < free_logit_ - kMargin) return OccupancyGrid::kFree;
    if (log_odds > occupied_logit_ + kMargin) return OccupancyGrid::kOccupied;
    return RenderBetween(log_odds);
  }

 private:
  int8_t RenderBetween(float log_odds) const;  // near the thresholds: exp() needed

  double free_threshold_, occupied_threshold_;
  double free_logit_, occupied_logit_;  // clearly past one of these: no exp() needed
};

// Global cells [min, max] (both included), in floor(map / resolution) indices.
struct CellBox {
  int min_col = 0;
  int min_row = 0;
  int max_col = -1;
  int max_row = -1;
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
  // How many never-observed cells inserting `scan` at `base_in_map` would observe (a
  // cell crossed by several beams counts once per beam). Changes nothing.
  int CountRevealedCells(const Pose2d& base_in_map, const LidarScan& scan) const;
  // The same count with another idea of "never observed": is_unobserved(col, row) on
  // global cell indices (floor(map / resolution)).
  template <class IsUnobserved>
  int CountBeamCells(const Pose2d& base_in_map, const LidarScan& scan,
                     IsUnobserved is_unobserved) const;

  // The grid's cells: global index of cell (0, 0) and size.
  struct Extent {
    int origin_col = 0;
    int origin_row = 0;
    int width = 0;
    int height = 0;
  };
  Extent extent() const { return {origin_col_, origin_row_, width_cells_, height_cells_}; }
  // Calls f(col, row, log_odds) for every observed cell, row by row (global indices).
  template <class F>
  void ForEachObserved(F f) const {
    ForEachObservedIn(
        {origin_col_, origin_row_, origin_col_ + width_cells_ - 1, origin_row_ + height_cells_ - 1},
        f);
  }
  // The same for the observed cells inside `box`.
  template <class F>
  void ForEachObservedIn(const CellBox& box, F f) const;
  // The log-odds of a global cell; NaN when never observed or outside the grid.
  float LogOddsAt(int col, int row) const;

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
  std::vector<BeamEnd> beam_ends_;  // scratch for InsertScan
};

template <class IsUnobserved>
int OccupancyMapper::CountBeamCells(const Pose2d& base_in_map, const LidarScan& scan,
                                    IsUnobserved is_unobserved) const {
  std::vector<BeamEnd> ends;
  int sensor_col = 0, sensor_row = 0;
  if (!BeamEndCells(base_in_map, scan, &ends, &sensor_col, &sensor_row)) return 0;
  int revealed = 0;
  for (const BeamEnd& end : ends) {
    // Every cell from the sensor's to the end cell (Bresenham).
    const int dx = std::abs(end.col - sensor_col), dy = std::abs(end.row - sensor_row);
    const int step_col = end.col > sensor_col ? 1 : -1, step_row = end.row > sensor_row ? 1 : -1;
    int col = sensor_col, row = sensor_row, err = dx - dy;
    while (true) {
      revealed += is_unobserved(col, row);
      if (col == end.col && row == end.row) break;
      const int twice = 2 * err;
      if (twice > -dy) err -= dy, col += step_col;
      if (twice < dx) err += dx, row += step_row;
    }
  }
  return revealed;
}

template <class F>
void OccupancyMapper::ForEachObservedIn(const CellBox& box, F f) const {
  const int first_col = std::max(0, box.min_col - origin_col_);
  const int last_col = std::min(width_cells_ - 1, box.max_col - origin_col_);
  const int first_row = std::max(0, box.min_row - origin_row_);
  const int last_row = std::min(height_cells_ - 1, box.max_row - origin_row_);
  for (int row = first_row; row <= last_row; ++row) {
    const Cell* cells = cells_.data() + static_cast<std::size_t>(row) * width_cells_;
    for (int col = first_col; col <= last_col; ++col) {
      if (!std::isnan(cells[col].log_odds))
        f(col + origin_col_, row + origin_row_, cells[col].log_odds);
    }
  }
}

}  // namespace aslam
