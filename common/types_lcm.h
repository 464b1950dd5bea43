#pragma once

// Translators between the shared value types and their lcmtypes. FromLcm
// functions validate: nullopt means the message is malformed and is to be
// dropped and counted by the caller.

#include <optional>
#include <string>

#include "aslam/lidar_scan_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/odometry_t.hpp"
#include "aslam/pose2d_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/occupancy_grid.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"

namespace aslam {

pose2d_t ToLcm(const Pose2d& pose);
Pose2d FromLcm(const pose2d_t& msg);

lidar_scan_t ToLcm(const LidarScan& scan);
// Rejects non-finite geometry and range_min >= range_max; single bad beams
// are the receiver's business (LidarScan::IsValidReturn).
std::optional<LidarScan> FromLcm(const lidar_scan_t& msg);

odometry_t ToLcm(const Odometry& odometry);
std::optional<Odometry> FromLcm(const odometry_t& msg);  // rejects non-finite values

velocity_command_t ToLcm(const VelocityCommand& command);
std::optional<VelocityCommand> FromLcm(const velocity_command_t& msg);  // rejects non-finite values

// `frame` is "map", "odom" or "world"; the covariance is zero (unknown).
pose_t ToLcm(const StampedPose& pose, const std::string& frame);
std::optional<StampedPose> FromLcm(const pose_t& msg);

// The frame SLAM publishes in and every consumer of SLAM_POSE and SLAM_MAP works in.
inline constexpr const char* kMapFrame = "map";
// SLAM_POSE as its consumers take it: a pose in any frame but kMapFrame is rejected too.
std::optional<StampedPose> MapFramePoseFromLcm(const pose_t& msg);

occupancy_grid_t ToLcm(const OccupancyGrid& grid, int64_t utime, int64_t revision,
                       const std::string& frame);
// Rejects sizes that disagree with num_cells, non-positive resolution,
// a rotated origin and cell values outside -1..100.
std::optional<OccupancyGrid> FromLcm(const occupancy_grid_t& msg);
// SLAM_MAP as its consumers take it: a grid in any frame but kMapFrame is rejected too.
std::optional<OccupancyGrid> MapFrameGridFromLcm(const occupancy_grid_t& msg);

// POSE_GRAPH: the graph plus the publisher's revision and loop-closure counts.
pose_graph_t ToLcm(const PoseGraph& graph, int64_t utime, int64_t revision,
                   int32_t loop_closures_accepted, int32_t loop_closures_rejected);
// Rejects counts that disagree with the arrays, ids not dense from 0 in order,
// non-finite poses, measurements or information, edges to missing nodes or to
// themselves, unknown edge kinds and asymmetric information matrices.
std::optional<PoseGraph> FromLcm(const pose_graph_t& msg);

}  // namespace aslam
