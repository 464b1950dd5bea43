#pragma once

// The g2o text format for 2D pose graphs (VERTEX_SE2 / EDGE_SE2 with the
// upper triangle of the information matrix), as read by g2o and Ceres'
// pose_graph_2d example.

#include <string>

#include "common/pose_graph.h"

namespace aslam {

// Writes `graph` to `path` atomically (common/atomic_file.h); throws std::runtime_error naming
// the path on failure.
void WriteG2o(const PoseGraph& graph, const std::string& path);
// Reads a g2o file; throws std::runtime_error naming the path and line on bad input.
// Loop closures are recognised as edges between non-consecutive ids.
PoseGraph ReadG2o(const std::string& path);

}  // namespace aslam
