#include "common/types_lcm.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <vector>

namespace aslam {
namespace {

// Deflate never expands more than about 1032:1, so a message claiming more cells than
// that per byte is refused before anything is allocated for it.
constexpr int64_t kMaxInflationRatio = 1032;
// zlib's default: on maps 2-3x smaller than level 1 for about 5x its time (some 10 ms per
// million cells, at most once a second), and every frame saved counts on a lossy link.
constexpr int kZlibLevel = 6;

bool Finite(const Pose2d& pose) {
  return std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.yaw_rad);
}

// The geometry both grid wire types share.
template <typename GridMsgT>
bool ValidGeometry(const GridMsgT& msg) {
  return msg.width_cells > 0 && msg.height_cells > 0 && msg.resolution_m > 0.0 &&
         std::isfinite(msg.resolution_m) && std::isfinite(msg.origin.x_m) &&
         std::isfinite(msg.origin.y_m) && msg.origin.yaw_rad == 0.0;
}

// Every cell is -1 (unknown) or an occupancy percentage.
bool ValidCellValues(const std::vector<int8_t>& cells) {
  // A branch-free min/max (vectorized): maps run to millions of cells.
  int8_t lowest = -1, highest = 100;
  for (const int8_t value : cells) {
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
  }
  return lowest >= -1 && highest <= 100;
}

template <typename GridMsgT>
std::optional<MapMessage> MapFrameGrid(const GridMsgT& msg) {
  if (msg.frame != kMapFrame) return std::nullopt;
  std::optional<OccupancyGrid> grid = FromLcm(msg);
  if (!grid) return std::nullopt;
  return MapMessage{msg.utime, msg.revision, std::move(*grid)};
}

bool Symmetric(const Eigen::Matrix3d& m) {
  for (int r = 0; r < 3; ++r) {
    for (int c = r + 1; c < 3; ++c) {
      const double a = m(r, c);
      const double b = m(c, r);
      // Relative: information entries span many orders of magnitude.
      if (std::abs(a - b) > 1e-9 * std::max({1.0, std::abs(a), std::abs(b)})) return false;
    }
  }
  return true;
}

}  // namespace

pose2d_t ToLcm(const Pose2d& pose) {
  pose2d_t msg{};
  msg.x_m = pose.x_m;
  msg.y_m = pose.y_m;
  msg.yaw_rad = pose.yaw_rad;
  return msg;
}

Pose2d FromLcm(const pose2d_t& msg) { return {msg.x_m, msg.y_m, msg.yaw_rad}; }

lidar_scan_t ToLcm(const LidarScan& scan) {
  lidar_scan_t msg{};
  msg.utime = scan.utime;
  msg.seq = scan.seq;
  msg.sensor_pose = ToLcm(scan.sensor_pose);
  msg.angle_min_rad = static_cast<float>(scan.angle_min_rad);
  msg.angle_increment_rad = static_cast<float>(scan.angle_increment_rad);
  msg.range_min_m = static_cast<float>(scan.range_min_m);
  msg.range_max_m = static_cast<float>(scan.range_max_m);
  msg.num_ranges = static_cast<int32_t>(scan.range_m.size());
  msg.range_m = scan.range_m;
  msg.num_beam_times = static_cast<int32_t>(scan.beam_time_s.size());
  msg.beam_time_s = scan.beam_time_s;
  return msg;
}

namespace {

// The geometry both scan wire types share; nullopt if it is unusable.
template <typename ScanMsgT>
std::optional<LidarScan> ScanGeometry(const ScanMsgT& msg) {
  LidarScan scan;
  scan.utime = msg.utime;
  scan.seq = msg.seq;
  scan.sensor_pose = FromLcm(msg.sensor_pose);
  scan.angle_min_rad = msg.angle_min_rad;
  scan.angle_increment_rad = msg.angle_increment_rad;
  scan.range_min_m = msg.range_min_m;
  scan.range_max_m = msg.range_max_m;
  if (!Finite(scan.sensor_pose) || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad) || !(scan.range_min_m >= 0.0) ||
      !(scan.range_max_m > scan.range_min_m) || !std::isfinite(scan.range_max_m)) {
    return std::nullopt;
  }
  scan.range_m = msg.range_m;
  return scan;
}

}  // namespace

std::optional<LidarScan> FromLcm(const lidar_scan_t& msg) {
  std::optional<LidarScan> scan = ScanGeometry(msg);
  if (!scan) return std::nullopt;
  if (!msg.beam_time_s.empty() && msg.beam_time_s.size() != msg.range_m.size()) {
    return std::nullopt;
  }
  for (const float t : msg.beam_time_s) {
    if (!(std::abs(t) <= kMaxBeamTimeS)) return std::nullopt;  // NaN fails too
  }
  scan->beam_time_s = msg.beam_time_s;
  return scan;
}

std::optional<LidarScan> FromLcm(const lidar_scan_v1_t& msg) {
  std::optional<LidarScan> scan = ScanGeometry(msg);
  if (!scan || !std::isfinite(msg.time_increment_s)) return std::nullopt;
  if (msg.time_increment_s != 0.0f) {
    scan->beam_time_s.resize(scan->range_m.size());
    for (std::size_t i = 0; i < scan->beam_time_s.size(); ++i) {
      scan->beam_time_s[i] = static_cast<float>(i * static_cast<double>(msg.time_increment_s));
      if (!(std::abs(scan->beam_time_s[i]) <= kMaxBeamTimeS)) return std::nullopt;
    }
  }
  return scan;
}

std::optional<LidarScan> DecodeLidarScan(const void* data, int size) {
  lidar_scan_t msg;
  if (msg.decode(data, 0, size) == size) return FromLcm(msg);
  lidar_scan_v1_t legacy;
  if (legacy.decode(data, 0, size) == size) return FromLcm(legacy);
  return std::nullopt;
}

void AddLidarScanSubscription(Subscriptions& subscriptions, const std::string& channel,
                              std::function<bool(const LidarScan&)> handler) {
  auto take = [handler = std::move(handler)](const std::optional<LidarScan>& scan) {
    return scan && handler(*scan);
  };
  subscriptions.AddWithLegacy<lidar_scan_t, lidar_scan_v1_t>(
      channel, [take](const lidar_scan_t& m) { return take(FromLcm(m)); },
      [take](const lidar_scan_v1_t& m) { return take(FromLcm(m)); });
}

odometry_t ToLcm(const Odometry& odometry) {
  odometry_t msg{};
  msg.utime = odometry.utime;
  msg.seq = odometry.seq;
  msg.pose = ToLcm(odometry.pose);
  msg.linear_velocity_mps = odometry.linear_velocity_mps;
  msg.angular_velocity_radps = odometry.angular_velocity_radps;
  return msg;
}

std::optional<Odometry> FromLcm(const odometry_t& msg) {
  Odometry odometry{msg.utime, msg.seq, FromLcm(msg.pose), msg.linear_velocity_mps,
                    msg.angular_velocity_radps};
  if (!Finite(odometry.pose) || !std::isfinite(odometry.linear_velocity_mps) ||
      !std::isfinite(odometry.angular_velocity_radps)) {
    return std::nullopt;
  }
  return odometry;
}

velocity_command_t ToLcm(const VelocityCommand& command) {
  velocity_command_t msg{};
  msg.utime = command.utime;
  msg.linear_mps = command.linear_mps;
  msg.angular_radps = command.angular_radps;
  return msg;
}

std::optional<VelocityCommand> FromLcm(const velocity_command_t& msg) {
  if (!std::isfinite(msg.linear_mps) || !std::isfinite(msg.angular_radps)) return std::nullopt;
  return VelocityCommand{msg.utime, msg.linear_mps, msg.angular_radps};
}

pose_t ToLcm(const StampedPose& pose, const std::string& frame) {
  pose_t msg{};
  msg.utime = pose.utime;
  msg.frame = frame;
  msg.pose = ToLcm(pose.pose);
  msg.linear_velocity_mps = pose.linear_velocity_mps;
  msg.angular_velocity_radps = pose.angular_velocity_radps;
  return msg;
}

std::optional<StampedPose> FromLcm(const pose_t& msg) {
  StampedPose pose{msg.utime, FromLcm(msg.pose), msg.linear_velocity_mps,
                   msg.angular_velocity_radps};
  if (!Finite(pose.pose)) return std::nullopt;
  return pose;
}

std::optional<StampedPose> MapFramePoseFromLcm(const pose_t& msg) {
  if (msg.frame != kMapFrame) return std::nullopt;
  return FromLcm(msg);
}

// The fields both grid wire types share.
template <typename GridMsgT>
GridMsgT GridHeader(const OccupancyGrid& grid, int64_t utime, int64_t revision,
                    const std::string& frame) {
  GridMsgT msg{};
  msg.utime = utime;
  msg.frame = frame;
  msg.revision = revision;
  msg.resolution_m = grid.resolution_m();
  msg.origin = ToLcm(Pose2d{grid.origin_m().x_m, grid.origin_m().y_m, 0.0});
  msg.width_cells = grid.width_cells();
  msg.height_cells = grid.height_cells();
  return msg;
}

occupancy_grid_t ToLcm(const OccupancyGrid& grid, int64_t utime, int64_t revision,
                       const std::string& frame) {
  occupancy_grid_t msg = GridHeader<occupancy_grid_t>(grid, utime, revision, frame);
  msg.num_cells = static_cast<int32_t>(grid.cells().size());
  msg.cells = grid.cells();
  return msg;
}

std::optional<OccupancyGrid> FromLcm(const occupancy_grid_t& msg) {
  if (!ValidGeometry(msg) ||
      static_cast<int64_t>(msg.width_cells) * msg.height_cells != msg.num_cells ||
      !ValidCellValues(msg.cells)) {
    return std::nullopt;
  }
  OccupancyGrid grid(msg.width_cells, msg.height_cells, msg.resolution_m,
                     {msg.origin.x_m, msg.origin.y_m});
  grid.mutable_cells() = msg.cells;
  return grid;
}

compressed_occupancy_grid_t ToCompressedLcm(const OccupancyGrid& grid, int64_t utime,
                                            int64_t revision, const std::string& frame) {
  compressed_occupancy_grid_t msg =
      GridHeader<compressed_occupancy_grid_t>(grid, utime, revision, frame);
  msg.encoding = compressed_occupancy_grid_t::ENCODING_ZLIB;
  const std::vector<int8_t>& cells = grid.cells();
  uLongf size = compressBound(static_cast<uLong>(cells.size()));
  msg.data.resize(size);
  // Only Z_MEM_ERROR can fail with a compressBound-sized buffer: as for any allocation.
  if (compress2(msg.data.data(), &size, reinterpret_cast<const Bytef*>(cells.data()),
                static_cast<uLong>(cells.size()), kZlibLevel) != Z_OK) {
    throw std::bad_alloc();
  }
  msg.data.resize(size);
  msg.num_bytes = static_cast<int32_t>(size);
  return msg;
}

std::optional<OccupancyGrid> FromLcm(const compressed_occupancy_grid_t& msg) {
  if (!ValidGeometry(msg) || msg.encoding != compressed_occupancy_grid_t::ENCODING_ZLIB ||
      msg.num_bytes != static_cast<int32_t>(msg.data.size())) {
    return std::nullopt;
  }
  const int64_t num_cells = static_cast<int64_t>(msg.width_cells) * msg.height_cells;
  if (num_cells > kMaxCompressedGridCells || num_cells > kMaxInflationRatio * msg.num_bytes) {
    return std::nullopt;
  }
  OccupancyGrid grid(msg.width_cells, msg.height_cells, msg.resolution_m,
                     {msg.origin.x_m, msg.origin.y_m});
  std::vector<int8_t>& cells = grid.mutable_cells();
  uLongf inflated = static_cast<uLongf>(cells.size());
  uLong consumed = static_cast<uLong>(msg.data.size());
  // Z_OK only when the stream ended; `consumed` then says whether bytes follow it.
  if (uncompress2(reinterpret_cast<Bytef*>(cells.data()), &inflated, msg.data.data(), &consumed) !=
          Z_OK ||
      inflated != cells.size() || consumed != msg.data.size() || !ValidCellValues(cells)) {
    return std::nullopt;
  }
  return grid;
}

std::optional<MapMessage> MapFrameGridFromLcm(const occupancy_grid_t& msg) {
  return MapFrameGrid(msg);
}

std::optional<MapMessage> MapFrameGridFromLcm(const compressed_occupancy_grid_t& msg) {
  return MapFrameGrid(msg);
}

void AddMapSubscription(Subscriptions& subscriptions, const std::string& channel,
                        std::function<bool(MapMessage)> handler) {
  auto take = [handler = std::move(handler)](std::optional<MapMessage> map) {
    return map && handler(std::move(*map));
  };
  subscriptions.AddWithLegacy<compressed_occupancy_grid_t, occupancy_grid_t>(
      channel,
      [take](const compressed_occupancy_grid_t& m) { return take(MapFrameGridFromLcm(m)); },
      [take](const occupancy_grid_t& m) { return take(MapFrameGridFromLcm(m)); });
}

pose_graph_t ToLcm(const PoseGraph& graph, int64_t utime, int64_t revision,
                   int32_t loop_closures_accepted, int32_t loop_closures_rejected) {
  pose_graph_t msg{};
  msg.utime = utime;
  msg.revision = revision;
  msg.loop_closures_accepted = loop_closures_accepted;
  msg.loop_closures_rejected = loop_closures_rejected;
  msg.num_nodes = static_cast<int32_t>(graph.nodes.size());
  msg.nodes.reserve(graph.nodes.size());
  for (const PoseGraphNode& node : graph.nodes) {
    pose_graph_node_t n{};
    n.id = node.id;
    n.utime = node.utime;
    n.pose = ToLcm(node.pose);
    msg.nodes.push_back(n);
  }
  msg.num_edges = static_cast<int32_t>(graph.edges.size());
  msg.edges.reserve(graph.edges.size());
  for (const PoseGraphEdge& edge : graph.edges) {
    pose_graph_edge_t e{};
    e.from_id = edge.from_id;
    e.to_id = edge.to_id;
    e.kind = edge.kind == EdgeKind::kLoopClosure ? pose_graph_edge_t::KIND_LOOP_CLOSURE
                                                 : pose_graph_edge_t::KIND_ODOMETRY;
    e.measurement = ToLcm(edge.measurement);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) e.information[3 * r + c] = edge.information(r, c);
    }
    msg.edges.push_back(e);
  }
  return msg;
}

std::optional<PoseGraph> FromLcm(const pose_graph_t& msg) {
  if (msg.num_nodes < 0 || msg.num_edges < 0 ||
      static_cast<std::size_t>(msg.num_nodes) != msg.nodes.size() ||
      static_cast<std::size_t>(msg.num_edges) != msg.edges.size()) {
    return std::nullopt;
  }
  PoseGraph graph;
  graph.nodes.reserve(msg.nodes.size());
  for (std::size_t i = 0; i < msg.nodes.size(); ++i) {
    const pose_graph_node_t& n = msg.nodes[i];
    PoseGraphNode node;
    node.id = n.id;
    node.utime = n.utime;
    node.pose = FromLcm(n.pose);
    if (node.id != static_cast<int>(i) || !Finite(node.pose)) return std::nullopt;
    graph.nodes.push_back(node);
  }
  graph.edges.reserve(msg.edges.size());
  for (const pose_graph_edge_t& e : msg.edges) {
    PoseGraphEdge edge;
    edge.from_id = e.from_id;
    edge.to_id = e.to_id;
    if (e.from_id < 0 || e.from_id >= msg.num_nodes || e.to_id < 0 || e.to_id >= msg.num_nodes ||
        e.from_id == e.to_id) {
      return std::nullopt;
    }
    if (e.kind == pose_graph_edge_t::KIND_ODOMETRY) {
      edge.kind = EdgeKind::kOdometry;
    } else if (e.kind == pose_graph_edge_t::KIND_LOOP_CLOSURE) {
      edge.kind = EdgeKind::kLoopClosure;
    } else {
      return std::nullopt;
    }
    edge.measurement = FromLcm(e.measurement);
    if (!Finite(edge.measurement)) return std::nullopt;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) edge.information(r, c) = e.information[3 * r + c];
    }
    if (!edge.information.allFinite() || !Symmetric(edge.information)) return std::nullopt;
    graph.edges.push_back(edge);
  }
  return graph;
}

}  // namespace aslam
