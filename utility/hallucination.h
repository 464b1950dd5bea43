#pragma once

// The hallucinated extension of docs/architecture.md §5 (U1, after Placed & Castellanos'
// Active Graph SLAM): the nodes and edges the pose graph would gain if the
// robot drove the planned path to a frontier, weighted by D-optimality.

#include <vector>

#include <Eigen/Core>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"
#include "utility/spanning_trees.h"

namespace aslam {

struct HallucinationOptions {     // docs/architecture.md §5 constants
  int path_cells_per_node = 100;  // ceil(path_cells / 100) nodes + one at the frontier
  // Σ_odo = [[xx, xy, 0], [xy, yy, 0], [0, 0, yawyaw]] (m², m², rad²).
  double odometry_sigma_xx = 0.04, odometry_sigma_xy = 0.001, odometry_sigma_yy = 0.04,
         odometry_sigma_yawyaw = 0.008;
  double unknown_radius_m = 1.0;  // u = fraction of unknown cells within this of the new node
  double loop_closure_radius_m = 2.0;
  int max_loop_closures_per_node = 5;
  int exclude_newest_nodes = 20;
  double occupied_fraction_threshold = 0.03;
  double loop_closure_scale = 1.5;
};

// I_odo = ½·inv(Σ_odo).
Eigen::Matrix3d OdometryInformation(const HallucinationOptions& options);

// The hallucinated extension for one frontier: `path_m` is the planned path
// robot → frontier target ("map", cell centres, from GlobalPath::points_m),
// `path_cells` its number of cells; new nodes chained to the newest graph
// node. Weights by D-optimality (spanning_trees.h).
// Interpretations (see hallucination.cc for the full list): the number of
// path cells is path_m.size(); "occupied" is a map value >= 65; the new node
// k (0-based) has index N + k in the extended graph, N = graph size.
// An empty graph or an empty path gives an empty extension. `options` must
// have passed ValidateHallucinationOptions.
GraphExtension HallucinatePath(const PoseGraph& graph, const std::vector<Point2d>& path_m,
                               const OccupancyGrid& map, const HallucinationOptions& options);

// The same extension with what it is made of, for tests and diagnostics.
struct HallucinatedNode {
  int path_index = 0;              // index into path_m
  Pose2d pose;                     // at path_m[path_index], yaw along the path
  double unknown_fraction = 0.0;   // u
  double occupied_fraction = 0.0;  // of the cells within unknown_radius_m
};
struct Hallucination {
  std::vector<HallucinatedNode> nodes;  // extended-graph index N + k for nodes[k]
  std::vector<PoseGraphEdge> edges;     // from/to in extended-graph indices, with I
  GraphExtension extension;             // the same edges with D-optimality weights
};
Hallucination HallucinatePathDetailed(const PoseGraph& graph, const std::vector<Point2d>& path_m,
                                      const OccupancyGrid& map,
                                      const HallucinationOptions& options);

// Validates; throws std::invalid_argument naming the field.
void ValidateHallucinationOptions(const HallucinationOptions& options);

}  // namespace aslam
