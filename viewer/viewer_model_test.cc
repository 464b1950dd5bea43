#include "viewer/viewer_model.h"

#include <glib.h>
#include <zlib.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "viewer/viewer_testing.h"

namespace aslam {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr int64_t kSecond = 1'000'000;

struct Tile {
  int x, y, w, h;
  std::vector<uint8_t> cells;
};

// Every tile of an update frame, inflated.
std::vector<Tile> Tiles(const std::string& frame) {
  std::vector<Tile> tiles;
  const std::regex tile(
      R"re(\{"x":(\d+),"y":(\d+),"w":(\d+),"h":(\d+),"cells":"([A-Za-z0-9+/=]*)"\})re");
  for (auto it = std::sregex_iterator(frame.begin(), frame.end(), tile);
       it != std::sregex_iterator(); ++it) {
    Tile t{std::stoi((*it)[1]), std::stoi((*it)[2]), std::stoi((*it)[3]), std::stoi((*it)[4]), {}};
    gsize z_size = 0;
    guchar* z = g_base64_decode((*it)[5].str().c_str(), &z_size);
    t.cells.resize(static_cast<std::size_t>(t.w) * t.h);
    uLongf size = t.cells.size();
    EXPECT_EQ(uncompress(t.cells.data(), &size, z, z_size), Z_OK);
    EXPECT_EQ(size, t.cells.size());
    g_free(z);
    tiles.push_back(std::move(t));
  }
  return tiles;
}

// A 150 x 100 grid (3 x 2 tiles): unknown, with a free room and a wall.
OccupancyGrid Floor(Point2d origin = {-2.0, -1.0}) {
  OccupancyGrid grid(150, 100, 0.05, origin);
  for (int row = 10; row < 60; ++row) {
    for (int col = 10; col < 120; ++col) grid.at({col, row}) = row == 59 ? 97 : 0;
  }
  return grid;
}

TEST(ViewerModel, TheFirstFrameHasTheWholeMapInTilesAndThenOnlyWhatChanged) {
  ViewerModel model;
  model.OnMap(Floor(), 1, kSecond);
  ViewerCursor page;
  const std::string first = Compact(model.Update(&page));
  EXPECT_THAT(first, HasSubstr("\"reset\":true"));
  EXPECT_THAT(first, HasSubstr("\"full\":true"));
  EXPECT_THAT(first, HasSubstr("\"width\":150,\"height\":100,\"resolution_m\":0.0500"));
  const std::vector<Tile> tiles = Tiles(first);
  // Tiles that are all unknown are not sent: the page starts from unknown. The room
  // (columns 10..119, rows 10..59) lies in tiles (0, 0) and (64, 0).
  ASSERT_EQ(tiles.size(), 2u);
  for (const Tile& t : tiles) {
    EXPECT_EQ(t.y, 0);
    for (int r = 0; r < t.h; ++r) {
      for (int c = 0; c < t.w; ++c) {
        const int8_t want = Floor().at({t.x + c, t.y + r});
        const uint8_t expected = want < 0 ? 255 : static_cast<uint8_t>(want == 97 ? 100 : want);
        ASSERT_EQ(t.cells[r * t.w + c], expected) << "tile " << t.x << "," << t.y;
      }
    }
  }

  EXPECT_EQ(model.Update(&page), "");  // nothing new

  OccupancyGrid changed = Floor();
  changed.at({70, 20}) = 100;  // one cell in tile (64, 0)
  changed.at({71, 20}) = 3;    // and one that quantizes to free: no change to send
  model.OnMap(changed, 2, 2 * kSecond);
  const std::string second = Compact(model.Update(&page));
  EXPECT_THAT(second, HasSubstr("\"full\":false"));
  const std::vector<Tile> changed_tiles = Tiles(second);
  ASSERT_EQ(changed_tiles.size(), 1u);
  EXPECT_EQ(changed_tiles[0].x, 64);
  EXPECT_EQ(changed_tiles[0].y, 0);
  EXPECT_EQ(changed_tiles[0].cells[20 * changed_tiles[0].w + (70 - 64)], 100);
}

TEST(ViewerModel, AGrownMapSendsOnlyTheTilesThatDifferAtTheirNewPlace) {
  ViewerModel model;
  model.OnMap(Floor(), 1, kSecond);
  ViewerCursor page;
  model.Update(&page);

  // The map grew by 64 cells to the left and down: the same floor, now at cell (74, 74).
  OccupancyGrid grown(214, 164, 0.05, {-2.0 - 64 * 0.05, -1.0 - 64 * 0.05});
  const OccupancyGrid floor = Floor();
  for (int row = 0; row < floor.height_cells(); ++row) {
    for (int col = 0; col < floor.width_cells(); ++col) {
      grown.at({col + 64, row + 64}) = floor.at({col, row});
    }
  }
  model.OnMap(grown, 2, 2 * kSecond);
  const std::string frame = Compact(model.Update(&page));
  EXPECT_THAT(frame, HasSubstr("\"full\":false"));
  EXPECT_THAT(frame, HasSubstr("\"width\":214"));
  EXPECT_TRUE(Tiles(frame).empty());  // the page moves what it has; nothing new to send

  grown.at({0, 0}) = 0;  // something new in the grown part
  model.OnMap(grown, 3, 3 * kSecond);
  const std::vector<Tile> tiles = Tiles(model.Update(&page));
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].x, 0);
  EXPECT_EQ(tiles[0].cells[0], 0);

  // Another resolution cannot be moved: the whole map again.
  model.OnMap(OccupancyGrid(10, 10, 0.1, {0.0, 0.0}, 0), 4, 4 * kSecond);
  EXPECT_THAT(Compact(model.Update(&page)), HasSubstr("\"full\":true"));
}

TEST(ViewerModel, EachPageHasItsOwnCursorAndAResetStartsAfresh) {
  ViewerModel model;
  model.OnPose(StampedPose{kSecond, {1.0, 2.0, 0.5}, 0.0, 0.0});
  ViewerCursor a;
  EXPECT_THAT(Compact(model.Update(&a)), HasSubstr("\"pose\":{\"x_m\":1.000,\"y_m\":2.000"));
  model.OnPose(StampedPose{2 * kSecond, {1.5, 2.0, 0.5}, 0.0, 0.0});
  const std::string a2 = Compact(model.Update(&a));
  EXPECT_THAT(a2, HasSubstr("\"trail_append\":[[1.50,2.00]]"));
  EXPECT_THAT(a2, Not(HasSubstr("reset")));

  ViewerCursor b;  // a page that connects later gets everything
  const std::string b1 = Compact(model.Update(&b));
  EXPECT_THAT(b1, HasSubstr("\"reset\":true"));
  EXPECT_THAT(b1, HasSubstr("\"trail\":[[1.00,2.00],[1.50,2.00]]"));

  a.reset_pending = true;  // a seek
  EXPECT_THAT(Compact(model.Update(&a)), HasSubstr("\"reset\":true"));
}

PoseGraph Chain(int nodes, double y_m = 0.1) {
  PoseGraph graph;
  for (int i = 0; i < nodes; ++i) {
    graph.nodes.push_back({i, i, {0.3 * i, y_m, 0.0}});
    if (i > 0) {
      PoseGraphEdge odometry;
      odometry.from_id = i - 1;
      odometry.to_id = i;
      graph.edges.push_back(odometry);
    }
  }
  return graph;
}

TEST(ViewerModel, TheTrailIsThePosesAfterTheNewestKeyframe) {
  ViewerModel model;
  ViewerCursor page;
  model.OnPose(StampedPose{kSecond, {0.0, 0.0, 0.0}, 0.0, 0.0});
  model.OnPose(StampedPose{kSecond + 1, {0.01, 0.0, 0.0}, 0.0, 0.0});  // under 5 cm: not kept
  model.OnPose(StampedPose{kSecond + 2, {0.3, 0.0, 0.0}, 0.0, 0.0});
  EXPECT_THAT(Compact(model.Update(&page)), HasSubstr("\"trail\":[[0.00,0.00],[0.30,0.00]]"));
  PoseGraph graph = Chain(2);  // optimized: 10 cm up from the poses
  PoseGraphEdge closure = graph.edges[0];
  closure.kind = EdgeKind::kLoopClosure;
  graph.edges.push_back(closure);
  model.OnGraph(graph, 2 * kSecond);
  const std::string frame = Compact(model.Update(&page));
  // Appended to the empty graph the page had.
  EXPECT_THAT(frame, HasSubstr("\"graph_append\":{\"nodes\":[[0.00,0.10],[0.30,0.10]],"
                               "\"edges\":[[0,1,0],[0,1,1]]}"));
  EXPECT_THAT(frame, HasSubstr("\"trail\":[[0.30,0.00]]"));  // the page draws the nodes first
}

TEST(ViewerModel, NewKeyframesAreAppendedUntilALoopClosureMovesTheOldOnes) {
  ViewerModel model;
  ViewerCursor page;
  model.OnGraph(Chain(3), kSecond);
  EXPECT_THAT(Compact(model.Update(&page)), HasSubstr("\"graph\":{\"nodes\":[[0.00,0.10],"));

  model.OnGraph(Chain(4), 2 * kSecond);  // one more keyframe, the others where they were
  const std::string appended = Compact(model.Update(&page));
  EXPECT_THAT(appended,
              HasSubstr("\"graph_append\":{\"nodes\":[[0.90,0.10]],\"edges\":[[2,3,0]]}"));
  EXPECT_THAT(appended, Not(HasSubstr("\"graph\":")));

  ViewerCursor late;  // a page that connects now gets the whole graph
  EXPECT_THAT(Compact(model.Update(&late)), HasSubstr("\"graph\":{\"nodes\":[[0.00,0.10],"
                                                      "[0.30,0.10],[0.60,0.10],[0.90,0.10]]"));

  model.OnGraph(Chain(5, /*y_m=*/0.15), 3 * kSecond);  // optimized: every node moved 5 cm
  const std::string moved = Compact(model.Update(&page));
  EXPECT_THAT(moved, HasSubstr("\"graph\":{\"nodes\":[[0.00,0.15],[0.30,0.15],"));
  EXPECT_THAT(moved, Not(HasSubstr("graph_append")));
}

FrontierList TwoFrontiers(int64_t utime, double second_x_m) {
  FrontierList list;
  list.utime = utime;
  for (const auto& [id, x] : std::vector<std::pair<int, double>>{{7, 1.0}, {8, second_x_m}}) {
    Frontier f;
    f.id = id;
    f.points_m = {{x, 2.0}, {x + 0.05, 2.0}};
    f.centroid_m = f.target_m = {x, 2.0};
    list.frontiers.push_back(f);
  }
  return list;
}

// Frontier cells are most of the traffic: a page gets them once per change of a frontier.
TEST(ViewerModel, AFrontiersCellsAreSentOnlyWhenThePageDoesNotHaveThem) {
  ViewerModel model;
  ViewerCursor page;
  model.OnFrontiers(TwoFrontiers(kSecond, 3.0));
  const std::string first = Compact(model.Update(&page));
  EXPECT_THAT(first, HasSubstr("{\"id\":7,\"centroid\":[1.00,2.00],\"target\":[1.00,2.00],"
                               "\"size\":2,\"cells\":[[1.00,2.00],[1.05,2.00]]}"));
  EXPECT_THAT(first, HasSubstr("\"id\":8,\"centroid\":[3.00,2.00],\"target\":[3.00,2.00],"
                               "\"size\":2,\"cells\":[[3.00,2.00],[3.05,2.00]]}"));

  model.OnFrontiers(TwoFrontiers(2 * kSecond, 3.5));  // frontier 8 moved, 7 did not
  const std::string second = Compact(model.Update(&page));
  EXPECT_THAT(second, HasSubstr("{\"id\":7,\"centroid\":[1.00,2.00],\"target\":[1.00,2.00],"
                                "\"size\":2}"));
  EXPECT_THAT(second, HasSubstr("\"cells\":[[3.50,2.00],[3.55,2.00]]"));

  ViewerCursor late;  // a new page has no cells at all
  EXPECT_THAT(Compact(model.Update(&late)), HasSubstr("\"cells\":[[1.00,2.00],[1.05,2.00]]"));
}

TEST(ViewerModel, ScoresCarryEveryTermAndNonFiniteTotalsAsNull) {
  ViewerModel model;
  ViewerScores scores;
  scores.decision_id = 4;
  scores.method = "ours";
  scores.chosen_frontier_id = 2;
  FrontierScore chosen;
  chosen.frontier_id = 2;
  chosen.u1 = 0.5;
  chosen.mean_entropy_bits = 0.25;
  chosen.ray_cells = 120;
  chosen.gamma = 0.125;
  chosen.rho = 10.0;
  chosen.u2 = 9.5;
  chosen.total = 5.0;
  chosen.chosen = true;
  FrontierScore blocked;
  blocked.frontier_id = 3;
  blocked.total = -std::numeric_limits<double>::infinity();
  blocked.eligibility = Eligibility::kBlacklisted;
  scores.scores = {chosen, blocked};
  model.OnScores(scores, kSecond);
  ViewerCursor page;
  const std::string frame = Compact(model.Update(&page));
  EXPECT_THAT(frame, HasSubstr("\"decision_id\":4,\"method\":\"ours\",\"chosen_frontier_id\":2"));
  EXPECT_THAT(frame, HasSubstr("\"u1\":0.5000,\"mean_entropy_bits\":0.2500,\"ray_cells\":120,"
                               "\"gamma\":0.1250,\"rho\":10.0000,\"u2\":9.5000,\"total\":5.0000,"
                               "\"eligible\":true"));
  EXPECT_THAT(frame, HasSubstr("\"total\":null,\"eligible\":false,\"reason\":\"blacklisted\""));
}

TEST(ViewerModel, TheSeriesHasOnePointPerSecondOfKnownAreaAndDOptimality) {
  ViewerModel model;
  model.OnMap(Floor(), 1, 10 * kSecond);
  for (int64_t t = 10 * kSecond; t <= 13 * kSecond; t += kSecond / 4) {
    model.OnPose(StampedPose{t, {}, 0.0, 0.0});
  }
  ASSERT_EQ(model.series().size(), 4u);  // 0, 1, 2, 3 s
  EXPECT_DOUBLE_EQ(model.series()[3][0], 3.0);
  EXPECT_NEAR(model.series()[3][1], 110 * 50 * 0.05 * 0.05, 1e-9);  // the room's cells
  EXPECT_TRUE(std::isnan(model.series()[3][2]));                    // no graph edges yet
  ViewerCursor page;
  EXPECT_THAT(Compact(model.Update(&page)),
              HasSubstr("\"series\":[[0.0,13.75,null],[1.0,13.75,null]"));
  model.OnPose(StampedPose{14 * kSecond, {}, 0.0, 0.0});
  EXPECT_THAT(Compact(model.Update(&page)), HasSubstr("\"series_append\":[[4.0,13.75,null]]"));
}

}  // namespace
}  // namespace aslam
