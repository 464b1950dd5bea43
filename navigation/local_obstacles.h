#pragma once

// The local obstacle layer: a window of the map around the robot plus the
// end points of the latest scan (so the robot does not hit what the map has
// not caught up with), as a distance field from OpenCV's distance transform.
// Rebuilt every control cycle; the DWA queries clearance from it.

#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"

namespace aslam {

struct LocalObstaclesOptions {
  double window_m = 8.0;          // side of the square window centred on the robot
  double resolution_m = 0.05;
  int occupied_threshold = 65;    // map cells >= this are obstacles
};

class LocalObstacles {
 public:
  LocalObstacles() = default;
  // `map` may be empty; `scan_points_m` are obstacle points in "map".
  LocalObstacles(const OccupancyGrid& map, const std::vector<Point2d>& scan_points_m,
                 const Pose2d& robot_in_map, const LocalObstaclesOptions& options);

  // Distance from `point_m` to the nearest obstacle, metres; points outside
  // the window read as 0 (treated as blocked, so rollouts stay inside).
  double ClearanceM(const Point2d& point_m) const;

 private:
  LocalObstaclesOptions options_;
  int size_cells_ = 0;
  Point2d origin_m_;
  std::vector<float> distance_m_;
};

}  // namespace aslam
