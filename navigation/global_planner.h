#pragma once

// Dijkstra on the 8-connected costmap. Edge cost = step length in cells
// (1 or sqrt 2) * (1 + cost_weight * c/253), where c is the costmap cost of
// the cell entered plus, for an unknown cell, CostmapOptions::unknown_cost
// (the unknown-cell penalty). Only traversable cells (cost < kInscribed) are
// entered, besides the start escape below; a diagonal step needs both
// orthogonal neighbours enterable (no corner cutting). One search from the
// robot gives path lengths and paths to any number of targets (what the
// utility needs per decision); a single-goal query (Plan) is an A* search
// that stops as soon as the goal is settled. Its heuristic is the octile
// distance or, given one, a goal-distance field (DistancesToGoal): a lower
// bound on the cost that goes around the walls, which in a building is far
// nearer the true cost, so A* settles a band along the corridors, not an
// ellipse through rooms and unknown space. Costs are accumulated in float (relative error
// ~1e-7 per step); the queue is an exact bucket queue (see .cc).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "navigation/costmap.h"

namespace aslam {

// A traversable start whose 4-connected traversable cells number at most this (1 m² at 5 cm) is
// shut in a pocket, and escapes it (GlobalPlannerOptions::start_escape_m).
inline constexpr std::size_t kStartPocketMaxCells = 400;

struct GlobalPlannerOptions {
  double cost_weight = 3.0;  // how strongly inflation costs push paths off walls
  // A start cell inside the inscribed zone (robot pressed against a wall) may
  // still be left: the search may cross non-lethal inscribed cells this far
  // (cell centres within this distance of the start's centre; only when the
  // start cell itself is not traversable). They cost as a cost-253 cell. A start
  // shut in a pocket of at most 1 m² of traversable cells (gaps the inscribed zone
  // closes) escapes from every cell of the pocket, this far plus the inscribed radius
  // (robot radius and clearance margin), so the way out spans a gap's inscribed cells.
  // Escape cells are only those whose clearance (to an obstacle cell's edge) is at least the
  // robot radius (the body fits, within its margin) or the start's own, if less (the DWA's
  // rule inside its margin: no closer than now): a hole narrower than the robot never opens.
  double start_escape_m = 0.3;

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

struct GlobalPath {
  std::vector<CellIndex> cells;   // start to goal, both included
  std::vector<Point2d> points_m;  // cell centres of `cells`
  double length_m = 0.0;          // geometric length along the cells
  double cost = 0.0;              // accumulated search cost
};

// The result of one search from a start cell: settled costs and parents.
class ShortestPathTree {
 public:
  ShortestPathTree() = default;
  bool Reachable(CellIndex cell) const;
  // Reachable = settled by the search (an early-stopped search leaves cells
  // beyond its targets unreachable).
  // Accumulated search cost to `cell`; +inf when unreachable.
  double CostTo(CellIndex cell) const;
  // Geometric length of the min-cost path to `cell`, metres; +inf when unreachable.
  double PathLengthM(CellIndex cell) const;
  // The min-cost path to `cell`; nullopt when unreachable.
  std::optional<GlobalPath> PathTo(CellIndex cell) const;
  CellIndex start() const { return start_; }
  // Cells settled by the search (the start included when on the map).
  std::size_t settled_count() const { return settled_count_; }
  // Searched on a costmap of this size, origin and resolution.
  bool SameGrid(const Costmap& costmap) const;

 private:
  friend class GlobalPlanner;
  // Index into the padded arrays (a one-cell border around the map), -1 off the map.
  int32_t PaddedIndex(CellIndex cell) const;
  CellIndex CellOf(int32_t padded_index) const;

  CellIndex start_;
  int width_cells_ = 0;
  int height_cells_ = 0;
  int padded_width_ = 0;  // width_cells_ + 2
  double resolution_m_ = 0.05;
  Point2d origin_m_;
  std::size_t settled_count_ = 0;
  float stopped_at_cost_ = 0.0f;  // the search's last settled cost (+inf when it ran out)
  // Per padded cell. A cell is settled iff `settled_` is set; cost_ and
  // length_cells_ of unsettled cells are tentative, parent_ may be stale.
  std::vector<float> cost_;
  std::vector<float> length_cells_;  // geometric path length in cells
  std::vector<int32_t> parent_;      // padded index of the parent, -1 for the start
  std::vector<uint8_t> settled_;
  // Search scratch kept so that a reused tree searches without allocating.
  std::vector<uint16_t> cell_class_;           // cost | unknown << 8 | escape << 9
  std::vector<std::vector<int32_t>> buckets_;  // the bucket queue
};

// Traversable cells within `radius_m` of `goal` that see it: no lethal cell on the Bresenham
// line between them, the goal's own cell aside. A goal the robot cannot stand on (a frontier
// target that the inflation or a newly seen obstacle has swallowed) is approached at one of these.
std::vector<CellIndex> GoalSnapCandidates(const Costmap& costmap, CellIndex goal, double radius_m);

// Where a path in `tree` towards `goal` ends: `goal` itself when the tree reaches it, else the
// reachable cell of `snap_candidates` (GoalSnapCandidates) nearest to it (ties: the cheaper);
// nullopt when there is none.
std::optional<CellIndex> ReachableGoalCell(const ShortestPathTree& tree, CellIndex goal,
                                           const std::vector<CellIndex>& snap_candidates);

class GlobalPlanner {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit GlobalPlanner(GlobalPlannerOptions options = {});

  // One-to-all search from `start` (stops early once every cell in `targets`
  // is settled, when `targets` is non-empty).
  ShortestPathTree Search(const Costmap& costmap, CellIndex start,
                          const std::vector<CellIndex>& targets = {}) const;
  // The same, into `tree`, reusing its memory (no allocation after the first
  // search on a map of the same size).
  void Search(const Costmap& costmap, CellIndex start, const std::vector<CellIndex>& targets,
              ShortestPathTree* tree) const;
  // Path from `start` to `goal` in metres ("map"); nullopt when the goal is
  // not traversable or not reachable. Searches in `scratch` when given (its
  // memory reused, as Search's).
  // `goal_distances`, when from DistancesToGoal for this goal's cell on a costmap of the same
  // grid, is A*'s heuristic (else the octile distance). It may be from an older costmap:
  // obstacles and costs added since keep it a lower bound; where an obstacle has gone, the
  // path stays valid and may cost a little more than the best until the field is renewed.
  std::optional<GlobalPath> Plan(const Costmap& costmap, Point2d start_m, Point2d goal_m,
                                 ShortestPathTree* scratch = nullptr,
                                 const ShortestPathTree* goal_distances = nullptr) const;
  // Every cell's cost to reach `goal` (read with CostTo) when unknown cells cost nothing extra:
  // a lower bound on every path's cost to `goal` in this costmap and in later ones that have
  // seen more of the unknown or found more obstacles (not in one where an obstacle has gone).
  // Cells are settled outwards from `goal` until `robot` is and then on to 1.25 x its cost
  // plus a margin (what a plan from `robot` or nearer can use); beyond, the field reads the
  // cost it stopped at, itself a lower bound there.
  void DistancesToGoal(const Costmap& costmap, CellIndex goal, CellIndex robot,
                       ShortestPathTree* field) const;

  const GlobalPlannerOptions& options() const { return options_; }

 private:
  enum class CostModel { kPlanning, kLowerBound };  // kLowerBound: see DistancesToGoal
  // Search, as A* towards `heuristic_goal` when given (same costs, far fewer cells settled),
  // with `goal_distances` as the heuristic where it has a value.
  // kLowerBound: the targets' first cell is the robot (see DistancesToGoal).
  void SearchImpl(const Costmap& costmap, CellIndex start, const std::vector<CellIndex>& targets,
                  std::optional<CellIndex> heuristic_goal, ShortestPathTree* tree,
                  const ShortestPathTree* goal_distances = nullptr,
                  CostModel model = CostModel::kPlanning) const;

  GlobalPlannerOptions options_;
};

}  // namespace aslam
