#pragma once

// Frontier extraction (no LCM): the borders between known free and unknown
// space in an occupancy grid, cut into segments the robot can look from, each
// with a reachable target cell, ids kept stable across map updates.
//
// 1. Frontier cells: map value in 0..free_threshold (known free) with an
//    8-neighbour at -1 (unknown). Off-map neighbours are not unknown (the SLAM
//    grid keeps a margin of unknown around everything it has seen).
// 2. Clusters: 8-connected, ordered by their first 2 x 2 block (blocks of
//    rows 2i..2i+1 and columns 2j..2j+1, in raster order of (i, j)); clusters of
//    fewer than min_size_m / resolution cells are dropped (specks of unknown
//    inside known free space make clusters of at most 8 cells).
// 3. Segments: a cluster's cells are ordered by geodesic distance (8-connected
//    steps of 1 or sqrt 2 cells, inside the cluster) from one of its ends (the
//    farthest cell from an arbitrary one); with L = that extent + one cell,
//    the cluster is cut into k = ceil(L / max_segment_length_m) pieces of
//    equal arc length. This follows bends (an L- or U-shaped frontier is cut
//    along itself, not across), unlike splitting along a principal axis.
// 4. Target: the cell nearest the centroid that is traversable in the
//    navigation Costmap and reachable from the robot, among the segment's
//    cells and the known-free cells within target_radius_m of the centroid
//    whose Bresenham line to the segment's cell nearest the centroid is all
//    known free (a place that looks at the frontier, never one across a wall
//    from it). Cells with room to stand come first: those whose clearance
//    (centre to the nearest edge of a cell that is not known free: an obstacle,
//    the unknown, an uncertain cell, off the map) is at least the robot's inscribed radius
//    (robot_radius_m + clearance_margin_m) + target_clearance_m; only when
//    there is none does the nearest traversable cell serve. A target pressed
//    into a nook between furniture and an unseen wall is where scan returns
//    the map does not hold (legs, ragged edges) shut the robot out; the lidar
//    sees the frontier as well from a step back. A segment without any target
//    is dropped: frontier_t has no "unreachable" flag and every published
//    target must be a goal the navigator can plan to.
// 5. Ids: greedy one-to-one matching of new segments to the previous call's
//    frontiers by centroid distance (closest pairs first, within
//    match_distance_m); unmatched segments get fresh ids, never reused.
//
// Reachability: traversable cells (cost < kInscribed) reachable by
// GlobalPlanner::Search are exactly the 4-connected component of the start's
// cell among traversable cells (the planner's diagonal steps need both
// orthogonal neighbours enterable, so every path it finds has a 4-connected
// twin), so labelling that component answers it in about a millisecond where a
// one-to-all Search takes tens on a campus-sized map: each row's runs of traversable
// cells, joined by union-find where they overlap a run of the row above (one pass over
// the costs, then work per run, not per cell). When the robot's cell
// is itself not traversable (pressed against a wall) or its component is a pocket of at most
// kStartPocketMaxCells, the planner's start escape decides, so one GlobalPlanner::Search from
// the robot is run instead.
// frontier_extractor_test checks the two agree.

#include <cstdint>
#include <opencv2/core.hpp>
#include <unordered_map>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "frontier/frontier.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"

namespace aslam {

struct FrontierOptions {
  // Map values <= this are known free. The SLAM renderer writes 0 for
  // p_occupied <= 0.25 and 1..64 for uncertain cells, which are not free.
  int free_threshold = 0;
  double min_size_m = 0.5;  // clusters with fewer than this / resolution cells are dropped
  double max_segment_length_m = 2.5;  // longer clusters are cut into equal pieces
  double target_radius_m = 1.0;       // target search around the centroid (besides the segment)
  double target_clearance_m = 0.15;   // targets with this much room beyond the inscribed radius
                                      // come first (step 4); 0: the nearest traversable cell
  double match_distance_m = 1.0;      // centroids this close keep the previous frontier's id
  // The navigator's own costmap options (nav.costmap with the robot's radius), so
  // "reachable" means the navigator will plan there.
  CostmapOptions costmap;
  GlobalPlannerOptions global_planner;  // start_escape_m: leaving a start pressed against a wall

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

// Which cells the robot can drive to from a start (see "Reachability" above).
class ReachableCells {
 public:
  ReachableCells() = default;  // nothing reachable until Compute()
  // Keeps a pointer to `costmap`, which must outlive the queries.
  ReachableCells(const Costmap& costmap, CellIndex start, const GlobalPlannerOptions& options) {
    Compute(costmap, start, options);
  }
  // The same, reusing this object's memory (nothing allocated for a map of the same size).
  void Compute(const Costmap& costmap, CellIndex start, const GlobalPlannerOptions& options);

  // Traversable and reachable from the start (false off the map).
  bool Reachable(CellIndex cell) const;
  // True when the start was not traversable, or shut in a pocket, and a GlobalPlanner search
  // decided.
  bool used_planner_search() const { return use_tree_; }

 private:
  struct Run {
    int col_begin = 0, col_end = 0;  // traversable cells [col_begin, col_end) of one row
  };
  const Costmap* costmap_ = nullptr;
  bool use_tree_ = false;
  ShortestPathTree tree_;
  std::vector<Run> runs_;               // every row's runs, row by row, left to right
  std::vector<int> row_first_run_;      // row r's runs: [row_first_run_[r], row_first_run_[r + 1])
  std::vector<int> run_parent_;         // union-find over runs
  std::vector<uint8_t> run_reachable_;  // per run, 1 = in the start's component
};

// Buffers kept between extractions, so that maps of one size allocate nothing new.
struct FrontierScratch {
  cv::Mat frontier;                       // step 1's mask, cleared cluster by cluster
  std::vector<CellIndex> frontier_cells;  // step 1's cells in raster order
  std::vector<uint8_t> unknown_padded, near_unknown_rows;  // step 1's working rows
  std::vector<CellIndex> cluster;
  // Step 3's result per kept cluster (cells in raster order), by a hash of its cells: from
  // the last extraction (reused when a cluster's cells are the same) and from this one.
  struct ClusterSegments {
    std::vector<CellIndex> cells;
    std::vector<std::vector<CellIndex>> segments;
  };
  using ClustersByHash = std::unordered_multimap<uint64_t, ClusterSegments>;
  ClustersByHash split_before, split_now;
  double split_resolution_m = 0.0;  // what split_before was split with
  double split_max_segment_length_m = 0.0;
  Costmap costmap;  // updated incrementally between maps (same costs as a fresh one)
  ReachableCells reachable;
  std::vector<CellIndex> target_offsets;  // step 4's search window, nearest offsets first
  // Step 4's room to stand: the offsets to check (RoomOffsets) and what they were made for.
  std::vector<CellIndex> room_offsets;
  double room_m = 0.0, room_resolution_m = 0.0;
};

// What the last extraction found and dropped.
struct FrontierExtractionStats {
  int frontier_cells = 0;
  int clusters = 0;  // before the size filter
  int clusters_too_small = 0;
  int clusters_split = 0;        // kept clusters cut into segments afresh (the rest: as last time)
  int segments = 0;              // from the clusters kept
  int segments_unreachable = 0;  // dropped: no reachable target
  bool used_planner_search = false;  // robot cell not traversable: reachability by GlobalPlanner
};

// Steps 1-4 for one map: segments with targets, ids left at -1.
// `robot_m` is the robot's position in the map's frame.
// `scratch` (optional) is reused memory.
std::vector<Frontier> FindFrontiers(const OccupancyGrid& map, Point2d robot_m,
                                    const FrontierOptions& options,
                                    FrontierExtractionStats* stats = nullptr,
                                    FrontierScratch* scratch = nullptr);

// Step 5: sets the ids of `frontiers` by matching them to `previous`; new ids
// start at *next_id, which is advanced. Sorts `frontiers` by id.
void AssignFrontierIds(const std::vector<Frontier>& previous, double match_distance_m,
                       std::vector<Frontier>* frontiers, int* next_id);

// The whole pipeline with the previous result kept for id matching.
class FrontierExtractor {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit FrontierExtractor(FrontierOptions options = {});

  // Frontiers of `map` seen from `robot_m` ("map" frame), sorted by id.
  const std::vector<Frontier>& Extract(const OccupancyGrid& map, Point2d robot_m);

  const std::vector<Frontier>& frontiers() const { return frontiers_; }
  const FrontierExtractionStats& last_stats() const { return stats_; }
  int next_id() const { return next_id_; }
  const FrontierOptions& options() const { return options_; }

 private:
  FrontierOptions options_;
  std::vector<Frontier> frontiers_;
  FrontierExtractionStats stats_;
  FrontierScratch scratch_;
  int next_id_ = 0;
};

}  // namespace aslam
