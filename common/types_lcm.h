#pragma once

// Translators between the shared value types and their lcmtypes. FromLcm
// functions validate: nullopt means the message is malformed and is to be
// dropped and counted by the caller.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "aslam/compressed_occupancy_grid_t.hpp"
#include "aslam/lidar_scan_t.hpp"
#include "aslam/lidar_scan_v1_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/odometry_t.hpp"
#include "aslam/pose2d_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/velocity_command_t.hpp"
#include "common/lcm_util.h"
#include "common/occupancy_grid.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"

namespace aslam {

pose2d_t ToLcm(const Pose2d& pose);
Pose2d FromLcm(const pose2d_t& msg);

lidar_scan_t ToLcm(const LidarScan& scan);
// Rejects non-finite geometry, range_min >= range_max, and beam times that are not
// absent or one per beam, finite and within kMaxBeamTimeS; single bad beams are the
// receiver's business (LidarScan::IsValidReturn).
std::optional<LidarScan> FromLcm(const lidar_scan_t& msg);
// A scan from a log written before beam times: beam i at i * time_increment_s.
std::optional<LidarScan> FromLcm(const lidar_scan_v1_t& msg);
// No lidar sweeps slower than 1 Hz; a beam time beyond this is garbage.
inline constexpr double kMaxBeamTimeS = 1.0;
// LIDAR_SCAN bytes of either wire type (a log may be older than beam times), decoded
// and validated; nullopt if they are neither or invalid.
std::optional<LidarScan> DecodeLidarScan(const void* data, int size);
// Subscribes `handler` to `channel` (LIDAR_SCAN) in both wire types; invalid scans are
// counted as rejected without reaching the handler.
void AddLidarScanSubscription(Subscriptions& subscriptions, const std::string& channel,
                              std::function<bool(const LidarScan&)> handler);

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

// The same grid with its cells zlib-compressed (an office floor: 400 kB -> 10-20 kB).
compressed_occupancy_grid_t ToCompressedLcm(const OccupancyGrid& grid, int64_t utime,
                                            int64_t revision, const std::string& frame);
// The most cells a compressed grid may claim (1.6 x 1.6 km at 5 cm cells), checked before
// inflating: a few bytes of zlib could otherwise ask for gigabytes.
inline constexpr int64_t kMaxCompressedGridCells = int64_t{1} << 30;
// Rejects what the raw FromLcm rejects, an unknown encoding, more than
// kMaxCompressedGridCells cells, and data that are not exactly one zlib stream of
// width x height cells.
std::optional<OccupancyGrid> FromLcm(const compressed_occupancy_grid_t& msg);

// SLAM_MAP as its consumers take it, from either of its wire types; a grid in any frame
// but kMapFrame is rejected too.
struct MapMessage {
  int64_t utime = 0;
  int64_t revision = 0;
  OccupancyGrid grid;
};
std::optional<MapMessage> MapFrameGridFromLcm(const occupancy_grid_t& msg);
std::optional<MapMessage> MapFrameGridFromLcm(const compressed_occupancy_grid_t& msg);
// Subscribes `handler` to `channel` (SLAM_MAP) in both wire types: SLAM publishes
// compressed_occupancy_grid_t, older logs and tools occupancy_grid_t. Maps in another
// frame or invalid are counted as rejected without reaching the handler.
void AddMapSubscription(Subscriptions& subscriptions, const std::string& channel,
                        std::function<bool(MapMessage)> handler);

// POSE_GRAPH: the graph plus the publisher's revision and loop-closure counts.
pose_graph_t ToLcm(const PoseGraph& graph, int64_t utime, int64_t revision,
                   int32_t loop_closures_accepted, int32_t loop_closures_rejected);
// Rejects counts that disagree with the arrays, ids not dense from 0 in order,
// non-finite poses, measurements or information, edges to missing nodes or to
// themselves, unknown edge kinds and asymmetric information matrices.
std::optional<PoseGraph> FromLcm(const pose_graph_t& msg);

}  // namespace aslam
