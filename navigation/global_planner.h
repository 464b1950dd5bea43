#pragma once

// Dijkstra on the 8-connected costmap. Edge cost = step length in cells
// (1 or sqrt 2) * (1 + cost_weight * cost/253) of the cell entered, plus the
// unknown-cell penalty. One search from the robot gives path lengths and
// paths to any number of targets (what the utility needs per decision); a
// single-goal query stops as soon as the goal is settled.

#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "navigation/costmap.h"

namespace aslam {

struct GlobalPlannerOptions {
  double cost_weight = 3.0;    // how strongly inflation costs push paths off walls
  // A start cell inside the inscribed zone (robot pressed against a wall) may
  // still be left: the search may cross non-lethal inscribed cells this far.
  double start_escape_m = 0.3;
};

struct GlobalPath {
  std::vector<CellIndex> cells;     // start to goal, both included
  std::vector<Point2d> points_m;    // cell centres of `cells`
  double length_m = 0.0;            // geometric length along the cells
  double cost = 0.0;                // accumulated search cost
};

// The result of one search from a start cell: settled costs and parents.
class ShortestPathTree {
 public:
  ShortestPathTree() = default;
  bool Reachable(CellIndex cell) const;
  // Accumulated search cost to `cell`; +inf when unreachable.
  double CostTo(CellIndex cell) const;
  // Geometric length of the min-cost path to `cell`, metres; +inf when unreachable.
  double PathLengthM(CellIndex cell) const;
  // The min-cost path to `cell`; nullopt when unreachable.
  std::optional<GlobalPath> PathTo(CellIndex cell) const;
  CellIndex start() const { return start_; }

 private:
  friend class GlobalPlanner;
  CellIndex start_;
  int width_cells_ = 0;
  int height_cells_ = 0;
  double resolution_m_ = 0.05;
  Point2d origin_m_;
  std::vector<double> cost_;
  std::vector<float> length_m_;
  std::vector<int32_t> parent_;  // linear index of the parent, -1 for none
};

class GlobalPlanner {
 public:
  explicit GlobalPlanner(GlobalPlannerOptions options = {});

  // One-to-all search from `start` (stops early once every cell in `targets`
  // is settled, when `targets` is non-empty).
  ShortestPathTree Search(const Costmap& costmap, CellIndex start,
                          const std::vector<CellIndex>& targets = {}) const;
  // Path from `start` to `goal` in metres ("map"); nullopt when the goal is
  // not traversable or not reachable.
  std::optional<GlobalPath> Plan(const Costmap& costmap, Point2d start_m, Point2d goal_m) const;

  const GlobalPlannerOptions& options() const { return options_; }

 private:
  GlobalPlannerOptions options_;
};

}  // namespace aslam
