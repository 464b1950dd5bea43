#include "common/types_lcm.h"

#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

// Encodes and decodes through LCM's wire format, as a subscriber would see it.
template <typename Msg>
Msg WireRoundTrip(const Msg& msg) {
  std::vector<uint8_t> buffer(msg.getEncodedSize());
  EXPECT_EQ(msg.encode(buffer.data(), 0, buffer.size()), static_cast<int>(buffer.size()));
  Msg decoded{};
  EXPECT_EQ(decoded.decode(buffer.data(), 0, buffer.size()), static_cast<int>(buffer.size()));
  return decoded;
}

TEST(TypesLcm, LidarScanRoundTrip) {
  LidarScan scan;
  scan.utime = 123456;
  scan.seq = 7;
  scan.angle_min_rad = -M_PI;
  scan.angle_increment_rad = 2 * M_PI / 4;
  scan.range_min_m = 0.15;
  scan.range_max_m = 12.0;
  scan.range_m = {1.0f, 0.0f, 11.5f, 3.25f};
  const auto back = FromLcm(WireRoundTrip(ToLcm(scan)));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->utime, 123456);
  EXPECT_EQ(back->seq, 7);
  EXPECT_EQ(back->range_m, scan.range_m);
  EXPECT_FLOAT_EQ(back->angle_increment_rad, static_cast<float>(M_PI / 2));
  EXPECT_TRUE(back->IsValidReturn(0));
  EXPECT_FALSE(back->IsValidReturn(1));  // 0 = no return
}

TEST(TypesLcm, LidarScanWithBrokenGeometryIsRejected) {
  LidarScan scan;
  scan.range_min_m = 1.0;
  scan.range_max_m = 0.5;
  EXPECT_FALSE(FromLcm(ToLcm(scan)).has_value());
  scan.range_max_m = 12.0;
  scan.angle_increment_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(FromLcm(ToLcm(scan)).has_value());
}

TEST(TypesLcm, BeamTimesTravelWithTheScanAndBadOnesAreRejected) {
  LidarScan scan;
  scan.range_max_m = 12.0;
  scan.range_m = {1.0f, 2.0f, 3.0f};
  scan.beam_time_s = {0.0f, 0.05f, 0.1f};
  const auto back = FromLcm(WireRoundTrip(ToLcm(scan)));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->beam_time_s, scan.beam_time_s);
  EXPECT_DOUBLE_EQ(back->BeamTimeS(2), 0.1f);

  lidar_scan_t msg = ToLcm(scan);
  msg.num_beam_times = 2;  // neither none nor one per beam
  msg.beam_time_s.resize(2);
  EXPECT_FALSE(FromLcm(msg).has_value());
  msg = ToLcm(scan);
  msg.beam_time_s[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(FromLcm(msg).has_value());
  msg.beam_time_s[1] = static_cast<float>(kMaxBeamTimeS) + 1.0f;
  EXPECT_FALSE(FromLcm(msg).has_value());
}

// The LIDAR_SCAN of logs written before beam times (lidar_scan_v1_t): still read.
lidar_scan_v1_t LegacyScan(float time_increment_s) {
  lidar_scan_v1_t legacy{};
  legacy.utime = 5000;
  legacy.angle_min_rad = -1.0f;
  legacy.angle_increment_rad = 0.5f;
  legacy.time_increment_s = time_increment_s;
  legacy.range_max_m = 10.0f;
  legacy.num_ranges = 4;
  legacy.range_m = {1.0f, 0.0f, 2.0f, 3.0f};
  return legacy;
}

std::vector<uint8_t> Encode(const lidar_scan_v1_t& msg) {
  std::vector<uint8_t> bytes(msg.getEncodedSize());
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

TEST(TypesLcm, OldLogsScansDecodeWithTheirBeamTimes) {
  const std::vector<uint8_t> swept = Encode(LegacyScan(0.01f));
  // Not a current lidar_scan_t: the fingerprint differs, so LCM refuses it...
  lidar_scan_t current;
  EXPECT_LT(current.decode(swept.data(), 0, static_cast<int>(swept.size())), 0);
  // ...and DecodeLidarScan reads it as the old type.
  const auto scan = DecodeLidarScan(swept.data(), static_cast<int>(swept.size()));
  ASSERT_TRUE(scan.has_value());
  EXPECT_EQ(scan->utime, 5000);
  EXPECT_EQ(scan->range_m, LegacyScan(0.01f).range_m);
  ASSERT_EQ(scan->beam_time_s.size(), 4u);
  EXPECT_FLOAT_EQ(scan->beam_time_s[3], 0.03f);
  // An instantaneous old sweep has no beam times.
  const std::vector<uint8_t> instant = Encode(LegacyScan(0.0f));
  const auto instant_scan = DecodeLidarScan(instant.data(), static_cast<int>(instant.size()));
  ASSERT_TRUE(instant_scan.has_value());
  EXPECT_TRUE(instant_scan->beam_time_s.empty());
  // Bytes of neither type are refused.
  const std::vector<uint8_t> garbage(40, 0x5a);
  EXPECT_FALSE(DecodeLidarScan(garbage.data(), static_cast<int>(garbage.size())).has_value());
}

TEST(TypesLcm, OdometryAndCommandRejectNonFinite) {
  Odometry odometry{10, 1, {1.0, 2.0, 0.5}, 0.2, -0.1};
  const auto back = FromLcm(WireRoundTrip(ToLcm(odometry)));
  ASSERT_TRUE(back.has_value());
  EXPECT_DOUBLE_EQ(back->pose.y_m, 2.0);
  EXPECT_DOUBLE_EQ(back->angular_velocity_radps, -0.1);
  odometry.pose.x_m = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(FromLcm(ToLcm(odometry)).has_value());

  VelocityCommand command{5, 0.3, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_FALSE(FromLcm(ToLcm(command)).has_value());
  command.angular_radps = 0.7;
  EXPECT_DOUBLE_EQ(FromLcm(WireRoundTrip(ToLcm(command)))->angular_radps, 0.7);
}

TEST(TypesLcm, OccupancyGridRoundTripAndValidation) {
  OccupancyGrid grid(3, 2, 0.05, {-1.0, 2.0});
  grid.at({2, 1}) = 100;
  grid.at({0, 0}) = 0;
  occupancy_grid_t msg = WireRoundTrip(ToLcm(grid, 99, 4, "map"));
  EXPECT_EQ(msg.frame, "map");
  EXPECT_EQ(msg.revision, 4);
  const auto back = FromLcm(msg);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->cells(), grid.cells());
  EXPECT_DOUBLE_EQ(back->origin_m().x_m, -1.0);

  occupancy_grid_t wrong_size = msg;
  wrong_size.width_cells = 4;
  EXPECT_FALSE(FromLcm(wrong_size).has_value());
  occupancy_grid_t bad_value = msg;
  bad_value.cells[1] = 101;
  EXPECT_FALSE(FromLcm(bad_value).has_value());
  occupancy_grid_t rotated = msg;
  rotated.origin.yaw_rad = 0.1;
  EXPECT_FALSE(FromLcm(rotated).has_value());
}

TEST(TypesLcm, OnlyTheMapFrameIsAcceptedFromSlam) {
  const StampedPose pose{10, {1.0, 2.0, 0.5}, 0.1, 0.0};
  const auto in_map = MapFramePoseFromLcm(ToLcm(pose, kMapFrame));
  ASSERT_TRUE(in_map.has_value());
  EXPECT_EQ(in_map->utime, 10);
  EXPECT_DOUBLE_EQ(in_map->pose.y_m, 2.0);
  EXPECT_FALSE(MapFramePoseFromLcm(ToLcm(pose, "odom")).has_value());
  EXPECT_FALSE(MapFramePoseFromLcm(ToLcm(pose, "world")).has_value());
  StampedPose not_finite = pose;
  not_finite.pose.x_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(MapFramePoseFromLcm(ToLcm(not_finite, kMapFrame)).has_value());

  OccupancyGrid grid(3, 2, 0.05, {-1.0, 2.0});
  grid.at({2, 1}) = 100;
  const auto grid_in_map = MapFrameGridFromLcm(ToLcm(grid, 99, 4, kMapFrame));
  ASSERT_TRUE(grid_in_map.has_value());
  EXPECT_EQ(grid_in_map->utime, 99);
  EXPECT_EQ(grid_in_map->revision, 4);
  EXPECT_EQ(grid_in_map->grid.cells(), grid.cells());
  EXPECT_FALSE(MapFrameGridFromLcm(ToLcm(grid, 99, 4, "world")).has_value());
  occupancy_grid_t bad_value = ToLcm(grid, 99, 4, kMapFrame);
  bad_value.cells[0] = -2;
  EXPECT_FALSE(MapFrameGridFromLcm(bad_value).has_value());

  const auto compressed_in_map = MapFrameGridFromLcm(ToCompressedLcm(grid, 98, 5, kMapFrame));
  ASSERT_TRUE(compressed_in_map.has_value());
  EXPECT_EQ(compressed_in_map->utime, 98);
  EXPECT_EQ(compressed_in_map->revision, 5);
  EXPECT_EQ(compressed_in_map->grid.cells(), grid.cells());
  EXPECT_FALSE(MapFrameGridFromLcm(ToCompressedLcm(grid, 98, 5, "world")).has_value());
}

// A map-like grid: unknown all round, a free room, walls, some partial probabilities.
OccupancyGrid RoomGrid() {
  OccupancyGrid grid(300, 200, 0.05, {-3.0, -2.5});
  for (int row = 40; row < 160; ++row) {
    for (int col = 50; col < 250; ++col) {
      const bool wall = row == 40 || row == 159 || col == 50 || col == 249;
      grid.at({col, row}) =
          wall ? 100 : static_cast<int8_t>((row * 7 + col * 3) % 11 == 0 ? 30 : 0);
    }
  }
  return grid;
}

TEST(TypesLcm, CompressedGridRoundTripsThroughTheWireAndIsSmall) {
  const OccupancyGrid grid = RoomGrid();
  const compressed_occupancy_grid_t msg = ToCompressedLcm(grid, 1234, 7, kMapFrame);
  EXPECT_EQ(msg.encoding, compressed_occupancy_grid_t::ENCODING_ZLIB);
  EXPECT_EQ(msg.num_bytes, static_cast<int32_t>(msg.data.size()));
  // Most of the 60000 cells are runs of -1 and 0.
  EXPECT_LT(msg.data.size() * 10, grid.cells().size());
  std::vector<uint8_t> wire(static_cast<std::size_t>(msg.getEncodedSize()));
  ASSERT_EQ(msg.encode(wire.data(), 0, static_cast<int>(wire.size())),
            static_cast<int>(wire.size()));
  compressed_occupancy_grid_t decoded{};
  ASSERT_EQ(decoded.decode(wire.data(), 0, static_cast<int>(wire.size())),
            static_cast<int>(wire.size()));
  const std::optional<OccupancyGrid> back = FromLcm(decoded);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->width_cells(), 300);
  EXPECT_EQ(back->height_cells(), 200);
  EXPECT_DOUBLE_EQ(back->resolution_m(), 0.05);
  EXPECT_DOUBLE_EQ(back->origin_m().x_m, -3.0);
  EXPECT_DOUBLE_EQ(back->origin_m().y_m, -2.5);
  EXPECT_EQ(back->cells(), grid.cells());
}

TEST(TypesLcm, CompressedGridRejectsWhatCannotBeTheMap) {
  const OccupancyGrid grid = RoomGrid();
  const compressed_occupancy_grid_t msg = ToCompressedLcm(grid, 1234, 7, kMapFrame);
  ASSERT_TRUE(FromLcm(msg).has_value());
  auto rejected = [&](const std::function<void(compressed_occupancy_grid_t&)>& change) {
    compressed_occupancy_grid_t bad = msg;
    change(bad);
    return !FromLcm(bad).has_value();
  };
  EXPECT_TRUE(rejected([](auto& m) { m.encoding = 2; }));
  EXPECT_TRUE(rejected([](auto& m) { m.width_cells = 299; }));   // inflates to too many cells
  EXPECT_TRUE(rejected([](auto& m) { m.height_cells = 201; }));  // to too few
  EXPECT_TRUE(rejected([](auto& m) { m.width_cells = 0; }));
  EXPECT_TRUE(rejected([](auto& m) { m.resolution_m = -0.05; }));
  EXPECT_TRUE(rejected([](auto& m) { m.origin.yaw_rad = 0.1; }));
  EXPECT_TRUE(rejected([](auto& m) { m.origin.x_m = std::numeric_limits<double>::infinity(); }));
  EXPECT_TRUE(rejected([](auto& m) { m.num_bytes -= 1; }));  // disagrees with data
  EXPECT_TRUE(rejected([](auto& m) {                         // stream cut short
    m.data.resize(m.data.size() / 2);
    m.num_bytes = static_cast<int32_t>(m.data.size());
  }));
  EXPECT_TRUE(rejected([](auto& m) {  // bytes after the stream's end
    m.data.push_back(0);
    m.num_bytes += 1;
  }));
  EXPECT_TRUE(rejected([](auto& m) { m.data[m.data.size() / 2] ^= 0x5a; }));  // damaged
  // A few bytes claiming a 1e9-cell grid: refused before anything is inflated.
  EXPECT_TRUE(rejected([](auto& m) {
    m.width_cells = 40000;
    m.height_cells = 25000;
  }));

  OccupancyGrid out_of_range = grid;
  out_of_range.at({0, 0}) = 101;
  EXPECT_FALSE(FromLcm(ToCompressedLcm(out_of_range, 1, 1, kMapFrame)).has_value());
}

PoseGraph SmallGraph() {
  PoseGraph graph;
  graph.nodes = {{0, 100, {0.0, 0.0, 0.0}}, {1, 200, {0.3, 0.01, 0.1}}, {2, 300, {0.6, -0.2, 3.1}}};
  PoseGraphEdge odometry;
  odometry.from_id = 0;
  odometry.to_id = 1;
  odometry.measurement = {0.3, 0.01, 0.1};
  odometry.information << 400.0, 1.5, -0.25, 1.5, 350.0, 0.125, -0.25, 0.125, 1e4;
  PoseGraphEdge closure = odometry;
  closure.from_id = 2;
  closure.to_id = 0;
  closure.kind = EdgeKind::kLoopClosure;
  closure.measurement = {-0.6, 0.2, -3.1};
  closure.information(0, 0) = 1.0 / 3.0;  // not exactly representable in decimal: still exact
  graph.edges = {odometry, closure};
  return graph;
}

TEST(TypesLcm, PoseGraphRoundTripIsExact) {
  const PoseGraph graph = SmallGraph();
  const pose_graph_t msg = WireRoundTrip(ToLcm(graph, 300, 7, 1, 2));
  EXPECT_EQ(msg.utime, 300);
  EXPECT_EQ(msg.revision, 7);
  EXPECT_EQ(msg.loop_closures_accepted, 1);
  EXPECT_EQ(msg.loop_closures_rejected, 2);
  EXPECT_EQ(msg.edges[1].kind, pose_graph_edge_t::KIND_LOOP_CLOSURE);
  EXPECT_EQ(msg.edges[0].information[1], 1.5);  // row-major
  const auto back = FromLcm(msg);
  ASSERT_TRUE(back.has_value());
  ASSERT_EQ(back->nodes.size(), graph.nodes.size());
  ASSERT_EQ(back->edges.size(), graph.edges.size());
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    EXPECT_EQ(back->nodes[i].id, graph.nodes[i].id);
    EXPECT_EQ(back->nodes[i].utime, graph.nodes[i].utime);
    EXPECT_EQ(back->nodes[i].pose.x_m, graph.nodes[i].pose.x_m);
    EXPECT_EQ(back->nodes[i].pose.y_m, graph.nodes[i].pose.y_m);
    EXPECT_EQ(back->nodes[i].pose.yaw_rad, graph.nodes[i].pose.yaw_rad);
  }
  for (std::size_t i = 0; i < graph.edges.size(); ++i) {
    EXPECT_EQ(back->edges[i].from_id, graph.edges[i].from_id);
    EXPECT_EQ(back->edges[i].to_id, graph.edges[i].to_id);
    EXPECT_EQ(back->edges[i].kind, graph.edges[i].kind);
    EXPECT_EQ(back->edges[i].measurement.x_m, graph.edges[i].measurement.x_m);
    EXPECT_EQ(back->edges[i].measurement.y_m, graph.edges[i].measurement.y_m);
    EXPECT_EQ(back->edges[i].measurement.yaw_rad, graph.edges[i].measurement.yaw_rad);
    EXPECT_EQ(back->edges[i].information, graph.edges[i].information);
  }
  // The empty graph (before the first keyframe) is valid too.
  const auto empty = FromLcm(WireRoundTrip(ToLcm(PoseGraph{}, 0, 0, 0, 0)));
  ASSERT_TRUE(empty.has_value());
  EXPECT_TRUE(empty->nodes.empty());
}

TEST(TypesLcm, MalformedPoseGraphsAreRejected) {
  const pose_graph_t good = ToLcm(SmallGraph(), 300, 7, 1, 2);
  ASSERT_TRUE(FromLcm(good).has_value());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<const char*, std::function<void(pose_graph_t*)>>> breaks = {
      {"num_nodes disagrees", [](pose_graph_t* m) { m->num_nodes = 2; }},
      {"num_edges disagrees", [](pose_graph_t* m) { m->num_edges = 3; }},
      {"ids not dense", [](pose_graph_t* m) { m->nodes[2].id = 3; }},
      {"ids out of order", [](pose_graph_t* m) { std::swap(m->nodes[0].id, m->nodes[1].id); }},
      {"node pose NaN", [nan](pose_graph_t* m) { m->nodes[1].pose.yaw_rad = nan; }},
      {"edge to a missing node", [](pose_graph_t* m) { m->edges[0].to_id = 3; }},
      {"negative id", [](pose_graph_t* m) { m->edges[1].from_id = -1; }},
      {"edge to itself", [](pose_graph_t* m) { m->edges[0].to_id = 0; }},
      {"unknown kind", [](pose_graph_t* m) { m->edges[0].kind = 2; }},
      {"measurement inf",
       [](pose_graph_t* m) {
         m->edges[1].measurement.x_m = std::numeric_limits<double>::infinity();
       }},
      {"information NaN", [nan](pose_graph_t* m) { m->edges[0].information[4] = nan; }},
      {"information asymmetric", [](pose_graph_t* m) { m->edges[1].information[5] = 0.5; }},
  };
  for (const auto& [what, apply] : breaks) {
    pose_graph_t bad = good;
    apply(&bad);
    EXPECT_FALSE(FromLcm(bad).has_value()) << what;
  }
}

}  // namespace
}  // namespace aslam
