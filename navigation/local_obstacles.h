#pragma once

// The local obstacle layer: a window of the map around the robot plus the
// end points of the latest scan (so the robot does not hit what the map has
// not caught up with), as a distance field from OpenCV's distance transform.
// Rebuilt every control cycle; the DWA queries clearance from it.
//
// Unknown map cells are not obstacles here: the robot drives into unknown
// space toward frontiers and the scan protects it there.

#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {

struct LocalObstaclesOptions {
  double window_m = 4.5;  // side of the square window centred on the robot
  double resolution_m = 0.05;
  int occupied_threshold = 65;  // map cells >= this are obstacles

  // Throws std::invalid_argument naming the option and its value.
  void Validate() const;
};

class LocalObstacles {
 public:
  LocalObstacles() = default;
  // `map` may be empty; `scan_points_m` are obstacle points in "map".
  // Aborts on invalid options: callers validate config at load time.
  LocalObstacles(const OccupancyGrid& map, const std::vector<Point2d>& scan_points_m,
                 const Pose2d& robot_in_map, const LocalObstaclesOptions& options);

  // Distance from `point_m` to the nearest obstacle, metres; points outside
  // the window read as 0 (treated as blocked, so rollouts stay inside).
  // Bilinear in the cell-centre distance field minus half a cell, so it is
  // the distance to the obstacle cell's edge and never more than half a cell
  // above the true distance to any obstacle point inside an obstacle cell.
  double ClearanceM(const Point2d& point_m) const;

  double resolution_m() const { return options_.resolution_m; }
  int size_cells() const { return size_cells_; }
  // Lower-left corner of the window's cell (0, 0), "map".
  Point2d origin_m() const { return origin_m_; }
  bool empty() const { return size_cells_ == 0; }

 private:
  LocalObstaclesOptions options_;
  int size_cells_ = 0;
  Point2d origin_m_;
  std::vector<float> distance_m_;  // row-major, row 0 at the bottom; cell centre to obstacle centre
};

}  // namespace aslam
