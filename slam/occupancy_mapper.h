#pragma once

// Log-odds occupancy mapping: every scan's beams are ray cast from its
// keyframe pose, cells along a beam get a miss, the end cell a hit. The grid
// grows to cover whatever is inserted. Rendered in the ROS convention.

#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/sensor_types.h"

namespace aslam {

struct OccupancyMapperOptions {
  double resolution_m = 0.05;
  double log_odds_hit = 0.85;     // added at a beam's end cell
  double log_odds_miss = -0.4;    // added to every cell the beam passes
  double log_odds_min = -2.0;     // clamps keep the map able to change
  double log_odds_max = 3.5;
  // A beam with no return clears this far (0: no-return beams are ignored).
  double no_return_clear_m = 0.0;
  double growth_margin_m = 2.0;   // extra border added whenever the grid grows
};

class OccupancyMapper {
 public:
  explicit OccupancyMapper(OccupancyMapperOptions options);

  void Clear();
  // Inserts one scan taken with the base at `base_in_map`.
  void InsertScan(const Pose2d& base_in_map, const LidarScan& scan);

  // -1 never observed, else round(100 * p_occupied).
  OccupancyGrid Render() const;
  bool empty() const;

  const OccupancyMapperOptions& options() const { return options_; }

 private:
  OccupancyMapperOptions options_;
  // log-odds per cell, NaN = never observed; grown on demand.
  int width_cells_ = 0;
  int height_cells_ = 0;
  Point2d origin_m_;
  std::vector<float> log_odds_;
};

}  // namespace aslam
