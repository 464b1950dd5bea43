#pragma once

// Translators from the SLAM library's outputs to the messages aslam-slam
// publishes: SLAM_POSE and POSE_GRAPH, in frame "map", and SLAM_MAP's publishing in either
// encoding (its translators: common/types_lcm.h).

#include <cstdint>

#include <Eigen/Core>
#include <lcm/lcm-cpp.hpp>

#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/occupancy_grid.h"
#include "common/sensor_types.h"
#include "slam/slam.h"
#include "slam/slam_config.h"

namespace aslam {

// SLAM_POSE: `pose` in "map" with its covariance over (x_m, y_m, yaw_rad).
pose_t SlamPoseToLcm(const StampedPose& pose, const Eigen::Matrix3d& covariance);

// POSE_GRAPH: the current graph with its revision and the loop-closure counters.
pose_graph_t SlamGraphToLcm(const Slam& slam, int64_t utime);

// Publishes `map` on SLAM_MAP in frame "map", zlib-compressed or raw as `encoding` says.
void PublishSlamMap(lcm::LCM& lcm, const OccupancyGrid& map, int64_t utime, int64_t revision,
                    SlamNodeOptions::MapEncoding encoding);

}  // namespace aslam
