#include "frontier/frontier_node.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "aslam/frontier_list_t.hpp"
#include "common/channels.h"
#include "common/inproc_host.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"

namespace aslam {
namespace {

constexpr double kRes = 0.05;

// A walled room (free cols 12..47 x rows 12..47) with an 11-cell doorway in
// its east wall at rows 25..35, unknown outside; with `north_door`, a second
// 12-cell doorway in its north wall at cols 15..26.
OccupancyGrid Room(bool north_door) {
  OccupancyGrid grid(60, 60, kRes, {0.0, 0.0}, OccupancyGrid::kUnknown);
  auto fill = [&](int col0, int row0, int col1, int row1, int8_t value) {
    for (int row = row0; row <= row1; ++row) {
      for (int col = col0; col <= col1; ++col) grid.at({col, row}) = value;
    }
  };
  fill(10, 10, 49, 49, OccupancyGrid::kOccupied);
  fill(12, 12, 47, 47, OccupancyGrid::kFree);
  fill(48, 25, 49, 35, OccupancyGrid::kFree);
  if (north_door) fill(15, 48, 26, 49, OccupancyGrid::kFree);
  return grid;
}

class FrontierNodeTest : public ::testing::Test {
 protected:
  FrontierNodeTest() : node_(host_.lcm(), FrontierOptions{}), listener_(host_.lcm()) {
    listener_.Add<frontier_list_t>(channels::kFrontiers, [this](const frontier_list_t& m) {
      lists_.push_back(m);
      return true;
    });
  }
  void PublishMap(const OccupancyGrid& grid, int64_t utime, int64_t revision,
                  const char* frame = "map") {
    const occupancy_grid_t msg = ToLcm(grid, utime, revision, frame);
    host_.lcm().publish(channels::kSlamMap, &msg);
    host_.DispatchPending();
  }
  void PublishPose(int64_t utime, Point2d position_m, const char* frame = "map") {
    const pose_t msg =
        ToLcm(StampedPose{utime, {position_m.x_m, position_m.y_m, 0.0}, 0.0, 0.0}, frame);
    host_.lcm().publish(channels::kSlamPose, &msg);
    host_.DispatchPending();
  }

  InProcessHost host_;
  FrontierNode node_;
  Subscriptions listener_;
  std::vector<frontier_list_t> lists_;
};

const Point2d kRoomCentre{1.5, 1.5};

TEST_F(FrontierNodeTest, AMapAndAPoseGiveOneExtractionPerMapRevision) {
  // A map before any pose waits for the pose.
  PublishMap(Room(false), 5'000'000, 7);
  EXPECT_TRUE(lists_.empty());
  PublishPose(5'100'000, kRoomCentre);
  ASSERT_EQ(lists_.size(), 1u);
  const frontier_list_t& first = lists_[0];
  EXPECT_EQ(first.utime, 5'000'000);  // the map's time, not the pose's
  EXPECT_EQ(first.map_revision, 7);
  ASSERT_EQ(first.num_frontiers, 1);
  const frontier_t& door = first.frontiers[0];
  EXPECT_EQ(door.id, 0);
  EXPECT_EQ(door.size_cells, 11);
  EXPECT_EQ(door.num_points, 11);
  EXPECT_DOUBLE_EQ(door.centroid_x_m, 49.5 * kRes);
  EXPECT_DOUBLE_EQ(door.centroid_y_m, 30.5 * kRes);
  // The extractor's target: in the room, where the robot has room to stand in front of the door
  // (frontier_extractor_test: RoomWithOneDoorwayGivesOneFrontierOfTheDoorwayWidth).
  EXPECT_DOUBLE_EQ(door.target_x_m, 41.5 * kRes);
  EXPECT_DOUBLE_EQ(door.target_y_m, 30.5 * kRes);
  for (int i = 0; i < door.num_points; ++i) {
    EXPECT_FLOAT_EQ(door.point_x_m[i], static_cast<float>(49.5 * kRes));
  }

  // More poses: nothing new.
  PublishPose(5'200'000, kRoomCentre);
  EXPECT_EQ(lists_.size(), 1u);

  // SLAM re-announcing revision 7 (a grid the extractor would answer differently, to tell a
  // re-announced list from a new extraction): the same list, restamped.
  PublishMap(Room(true), 6'000'000, 7);
  ASSERT_EQ(lists_.size(), 2u);
  EXPECT_EQ(lists_[1].utime, 6'000'000);
  EXPECT_EQ(lists_[1].map_revision, 7);
  ASSERT_EQ(lists_[1].num_frontiers, 1);
  EXPECT_EQ(lists_[1].frontiers[0].size_cells, 11);

  // A new revision with a second doorway: the first keeps its id.
  PublishMap(Room(true), 7'000'000, 8);
  ASSERT_EQ(lists_.size(), 3u);
  EXPECT_EQ(lists_[2].utime, 7'000'000);
  EXPECT_EQ(lists_[2].map_revision, 8);
  ASSERT_EQ(lists_[2].num_frontiers, 2);
  EXPECT_EQ(lists_[2].frontiers[0].id, 0);
  EXPECT_DOUBLE_EQ(lists_[2].frontiers[0].centroid_x_m, 49.5 * kRes);
  EXPECT_EQ(lists_[2].frontiers[1].id, 1);
  EXPECT_EQ(lists_[2].frontiers[1].size_cells, 12);

  // What the utility reads back is what the extractor found.
  const auto decoded = FromLcm(lists_[2]);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->map_revision, 8);
  ASSERT_EQ(decoded->frontiers.size(), node_.extractor().frontiers().size());
  for (std::size_t i = 0; i < decoded->frontiers.size(); ++i) {
    EXPECT_EQ(decoded->frontiers[i].id, node_.extractor().frontiers()[i].id);
    EXPECT_DOUBLE_EQ(decoded->frontiers[i].target_m.x_m,
                     node_.extractor().frontiers()[i].target_m.x_m);
  }
  EXPECT_EQ(node_.lists_published(), 3);
  EXPECT_EQ(node_.subscriptions().total_dropped(), 0);
}

TEST_F(FrontierNodeTest, ARobotOffTheMapGetsAnEmptyList) {
  PublishPose(1'000'000, {-5.0, -5.0});
  PublishMap(Room(true), 1'000'000, 1);
  ASSERT_EQ(lists_.size(), 1u);
  EXPECT_EQ(lists_[0].num_frontiers, 0);
  EXPECT_EQ(lists_[0].map_revision, 1);
}

TEST_F(FrontierNodeTest, BadMessagesAreDroppedAndCounted) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const char garbage[] = "not a message";
  host_.lcm().publish(channels::kSlamMap, garbage, sizeof(garbage));
  host_.lcm().publish(channels::kSlamPose, garbage, sizeof(garbage));
  host_.DispatchPending();
  PublishMap(Room(false), 1'000'000, 1, "world");  // wrong frame
  OccupancyGrid grid = Room(false);
  occupancy_grid_t short_map = ToLcm(grid, 1'000'000, 2, "map");
  short_map.num_cells = 50;  // disagrees with 60 x 60
  short_map.cells.resize(50);
  host_.lcm().publish(channels::kSlamMap, &short_map);
  occupancy_grid_t bad_value = ToLcm(grid, 1'000'000, 3, "map");
  bad_value.cells[100] = 101;
  host_.lcm().publish(channels::kSlamMap, &bad_value);
  occupancy_grid_t no_resolution = ToLcm(grid, 1'000'000, 4, "map");
  no_resolution.resolution_m = 0.0;
  host_.lcm().publish(channels::kSlamMap, &no_resolution);
  host_.DispatchPending();
  PublishPose(1'000'000, kRoomCentre, "odom");  // wrong frame
  PublishPose(1'000'000, {nan, 1.0});

  const Subscriptions& subs = node_.subscriptions();
  EXPECT_EQ(subs.stats(channels::kSlamMap).decode_failures, 1);
  EXPECT_EQ(subs.stats(channels::kSlamMap).rejected, 4);
  EXPECT_EQ(subs.stats(channels::kSlamPose).decode_failures, 1);
  EXPECT_EQ(subs.stats(channels::kSlamPose).rejected, 2);
  EXPECT_EQ(subs.total_dropped(), 8);
  EXPECT_TRUE(lists_.empty());

  // Valid messages still get through.
  PublishMap(Room(false), 2'000'000, 5);
  PublishPose(2'000'000, kRoomCentre);
  ASSERT_EQ(lists_.size(), 1u);
  EXPECT_EQ(lists_[0].map_revision, 5);
  EXPECT_EQ(lists_[0].num_frontiers, 1);
  EXPECT_EQ(subs.total_dropped(), 8);
}

// ---------------------------------------------------------------------------
// FRONTIERS translators

FrontierList SampleList() {
  FrontierList list;
  list.utime = 123;
  list.map_revision = 9;
  Frontier a;
  a.id = 4;
  a.cells = {{1, 2}, {1, 3}};
  a.points_m = {{0.075, 0.125}, {0.075, 0.175}};
  a.centroid_m = {0.075, 0.15};
  a.target_m = {0.025, 0.125};
  Frontier b;
  b.id = 11;
  b.points_m = {{-1.5, 2.25}};
  b.centroid_m = {-1.5, 2.25};
  b.target_m = {-1.0, 2.0};
  list.frontiers = {a, b};
  return list;
}

TEST(FrontierLcm, RoundTrips) {
  const FrontierList list = SampleList();
  const frontier_list_t msg = ToLcm(list);
  EXPECT_EQ(msg.num_frontiers, 2);
  EXPECT_EQ(msg.frontiers[0].size_cells, 2);
  EXPECT_EQ(msg.frontiers[0].num_points, 2);
  const auto back = FromLcm(msg);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->utime, 123);
  EXPECT_EQ(back->map_revision, 9);
  ASSERT_EQ(back->frontiers.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const Frontier& in = list.frontiers[i];
    const Frontier& out = back->frontiers[i];
    EXPECT_EQ(out.id, in.id);
    EXPECT_EQ(out.size_cells(), in.size_cells());
    EXPECT_DOUBLE_EQ(out.centroid_m.x_m, in.centroid_m.x_m);
    EXPECT_DOUBLE_EQ(out.centroid_m.y_m, in.centroid_m.y_m);
    EXPECT_DOUBLE_EQ(out.target_m.x_m, in.target_m.x_m);
    EXPECT_DOUBLE_EQ(out.target_m.y_m, in.target_m.y_m);
    ASSERT_EQ(out.points_m.size(), in.points_m.size());
    for (std::size_t k = 0; k < in.points_m.size(); ++k) {
      EXPECT_FLOAT_EQ(static_cast<float>(out.points_m[k].x_m),
                      static_cast<float>(in.points_m[k].x_m));
      EXPECT_FLOAT_EQ(static_cast<float>(out.points_m[k].y_m),
                      static_cast<float>(in.points_m[k].y_m));
    }
    EXPECT_TRUE(out.cells.empty());  // not carried
  }
  // Encoded and decoded through LCM's own wire format too.
  std::vector<uint8_t> bytes(msg.getEncodedSize());
  ASSERT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  frontier_list_t decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_TRUE(FromLcm(decoded).has_value());
  // An empty list is valid.
  EXPECT_TRUE(FromLcm(ToLcm(FrontierList{})).has_value());
}

TEST(FrontierLcm, MalformedListsAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const frontier_list_t good = ToLcm(SampleList());
  ASSERT_TRUE(FromLcm(good).has_value());
  auto rejected = [&](auto mutate) {
    frontier_list_t msg = good;
    mutate(msg);
    return !FromLcm(msg).has_value();
  };
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.num_frontiers = 3; }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.num_frontiers = -1; }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.frontiers[0].num_points = 3; }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.frontiers[0].point_y_m.pop_back(); }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.frontiers[0].size_cells = 5; }));
  EXPECT_TRUE(rejected([&](frontier_list_t& m) { m.frontiers[1].centroid_x_m = nan; }));
  EXPECT_TRUE(rejected([&](frontier_list_t& m) { m.frontiers[1].target_y_m = inf; }));
  EXPECT_TRUE(
      rejected([&](frontier_list_t& m) { m.frontiers[0].point_x_m[1] = static_cast<float>(nan); }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.frontiers[1].id = -2; }));
  EXPECT_TRUE(rejected([](frontier_list_t& m) { m.frontiers[1].id = m.frontiers[0].id; }));
}

}  // namespace
}  // namespace aslam
