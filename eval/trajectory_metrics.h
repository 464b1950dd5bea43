#pragma once

// Evaluation of a SLAM run against ground truth (docs/architecture.md §6): absolute
// trajectory error of keyframe poses against truth samples matched by utime,
// and how well the SLAM occupancy grid agrees with the true map. Pure C++,
// no LCM: the bench tool and the replay test feed it decoded values.
//
// Frames: estimates are in "map" (anchored at the first keyframe), truth in
// "world". ComputeAte expresses the truth relative to its pose at the first
// estimate's time: no best-fit alignment hides drift.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"

namespace aslam {

struct TimedPose {
  int64_t utime = 0;
  Pose2d pose;
};

// The keyframe poses of a graph, in node order.
std::vector<TimedPose> KeyframePoses(const PoseGraph& graph);

// The pose at `utime` from samples sorted by utime: linear interpolation
// (yaw the short way) between the neighbouring samples when both lie within
// `max_gap_us` of `utime`, else the nearest sample if it lies within
// `max_gap_us`, else nullopt (also for empty samples).
std::optional<Pose2d> PoseAt(const std::vector<TimedPose>& samples, int64_t utime,
                             int64_t max_gap_us);

// `samples` re-expressed relative to `anchor`: anchor⁻¹ ⊕ sample.
std::vector<TimedPose> RelativeTo(const Pose2d& anchor, const std::vector<TimedPose>& samples);

struct AteOptions {
  // Truth farther than this from an estimate's utime leaves it unmatched.
  int64_t max_time_gap_us = 100000;
};

struct AteResult {
  int matched = 0;      // estimates with a truth pose
  int unmatched = 0;    // estimates without one (not in the statistics)
  double rmse_m = 0.0;  // translation error
  double mean_m = 0.0;
  double max_m = 0.0;
  int64_t max_utime = 0;  // where the largest translation error occurs
  double yaw_rmse_rad = 0.0;
  double yaw_max_rad = 0.0;
  // Per matched estimate, in estimate order: translation error.
  std::vector<double> errors_m;
};

// ATE of `estimate` (in "map", any order) against `truth` (in "world",
// sorted by utime). The truth is anchored at the first matched estimate t0:
// truth_in_map(t) = truth(t0)⁻¹ ⊕ truth(t). SLAM keyframes need nothing
// more (the first is the identity); other estimates (odometry) are to be made
// relative to their pose at t0 first (RelativeTo).
AteResult ComputeAte(const std::vector<TimedPose>& estimate, const std::vector<TimedPose>& truth,
                     const AteOptions& options = AteOptions());

struct MapAgreementOptions {
  int occupied_min = 65;  // SLAM cells with value >= this are occupied
  int free_max = 25;      // SLAM cells with value <= this (and >= 0) are free
  // A SLAM-occupied cell is right when a solid truth cell (occupied or
  // unknown) lies within this distance, centre to centre.
  double wall_tolerance_m = 0.10;
  // A SLAM-free cell is right when a free truth cell lies within this
  // distance (0: the truth cell under its centre must be free). One cell
  // absorbs the half-cell offset between the two grids.
  double free_tolerance_m = 0.05;
};

struct MapAgreement {
  int64_t slam_occupied_cells = 0;
  int64_t occupied_near_wall = 0;
  double occupied_precision = 0.0;  // occupied_near_wall / slam_occupied_cells (0 if none)
  int64_t slam_free_cells = 0;
  int64_t free_truly_free = 0;
  double free_precision = 0.0;  // free_truly_free / slam_free_cells (0 if none)
  int64_t truth_free_cells = 0;
  int64_t truth_free_known = 0;  // truly free cells the SLAM map marks known (any value)
  double coverage = 0.0;         // truth_free_known / truth_free_cells (docs/architecture.md §6)
};

// Coverage alone (docs/architecture.md §6): the share of truly free cells that `slam_map`,
// placed in the world by `map_in_world`, marks known. Much cheaper than the
// whole agreement, for a coverage timeline.
struct Coverage {
  int64_t truth_free_cells = 0;
  int64_t truth_free_known = 0;
  double fraction = 0.0;  // truth_free_known / truth_free_cells (0 if none)
};
Coverage ComputeCoverage(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                         const OccupancyGrid& truth);

// ComputeCoverage for a timeline: the truth's free cells are placed in "map"
// once, so each map costs one lookup per truly free cell (same result).
class CoverageEvaluator {
 public:
  CoverageEvaluator(const OccupancyGrid& truth, const Pose2d& map_in_world);
  // Cheap for a map on the grid of the previous call (same size, resolution, origin).
  Coverage Evaluate(const OccupancyGrid& slam_map);

 private:
  struct MapGeometry {
    int width_cells = 0;
    int height_cells = 0;
    double resolution_m = 0.0;
    Point2d origin_m;
    bool operator==(const MapGeometry& o) const {
      return width_cells == o.width_cells && height_cells == o.height_cells &&
             resolution_m == o.resolution_m && origin_m.x_m == o.origin_m.x_m &&
             origin_m.y_m == o.origin_m.y_m;
    }
  };
  std::vector<Point2d> truth_free_in_map_m_;  // centres of the truly free cells, in "map"
  MapGeometry geometry_;                      // of the map cell_indices_ was placed on
  std::vector<std::size_t> cell_indices_;     // truly free cells on that map, in memory order
};

// Compares `slam_map` (in "map") with `truth` (in "world"), the SLAM map
// placed in the world by `map_in_world` (the true pose of the first
// keyframe). Truth cells off the grid count as solid, as in the simulator.
MapAgreement ComputeMapAgreement(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                                 const OccupancyGrid& truth,
                                 const MapAgreementOptions& options = MapAgreementOptions());

}  // namespace aslam
