#pragma once

// Translators from the SLAM library's outputs to the messages aslam-slam
// publishes: SLAM_POSE, POSE_GRAPH and SLAM_MAP, all in frame "map".

#include <cstdint>

#include <Eigen/Core>

#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/occupancy_grid.h"
#include "common/sensor_types.h"
#include "slam/slam.h"

namespace aslam {

// SLAM_POSE: `pose` in "map" with its covariance over (x_m, y_m, yaw_rad).
pose_t SlamPoseToLcm(const StampedPose& pose, const Eigen::Matrix3d& covariance);

// POSE_GRAPH: the current graph with its revision and the loop-closure counters.
pose_graph_t SlamGraphToLcm(const Slam& slam, int64_t utime);

// SLAM_MAP: the rendered map with its revision.
occupancy_grid_t SlamMapToLcm(const OccupancyGrid& map, int64_t utime, int64_t revision);

}  // namespace aslam
