#pragma once

// The pose graph as a value type: keyframe nodes and relative-pose edges with
// 3x3 information matrices. Shared by SLAM (which builds it), the utility
// (which scores it) and the metrics; POSE_GRAPH carries it on LCM.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/pose2d.h"

namespace aslam {

enum class EdgeKind : int8_t { kOdometry = 0, kLoopClosure = 1 };

struct PoseGraphNode {
  int id = 0;         // dense from 0: nodes[i].id == i
  int64_t utime = 0;  // time of the keyframe's scan
  Pose2d pose;        // estimate in "map"
};

struct PoseGraphEdge {
  int from_id = 0;
  int to_id = 0;
  EdgeKind kind = EdgeKind::kOdometry;
  Pose2d measurement;                                         // pose of `to` in the frame of `from`
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // over (x_m, y_m, yaw_rad)
};

struct PoseGraph {
  std::vector<PoseGraphNode> nodes;
  std::vector<PoseGraphEdge> edges;
};

}  // namespace aslam
