#include "worlds/worldgen.h"
#include "common/test_temp_dir.h"
#include "common/world_file.h"

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <opencv2/imgproc.hpp>

namespace aslam {
namespace {

namespace fs = std::filesystem;

// The checks below use OpenCV directly rather than the generator's own
// helpers, so a generator bug cannot hide behind a shared one.

cv::Mat FreeMask(const OccupancyGrid& grid) {
  const cv::Mat cells(grid.height_cells(), grid.width_cells(), CV_8S,
                      const_cast<int8_t*>(grid.cells().data()));
  return cells == OccupancyGrid::kFree;
}

double FreeArea(const OccupancyGrid& grid) {
  return cv::countNonZero(FreeMask(grid)) * grid.resolution_m() * grid.resolution_m();
}

cv::Point StartCell(const OccupancyGrid& grid, const Pose2d& start) {
  const CellIndex cell = grid.WorldToCell({start.x_m, start.y_m});
  return {cell.col, cell.row};
}

// Free cells 4-connected to the start.
int ReachableCells(const OccupancyGrid& grid, const Pose2d& start) {
  cv::Mat free = FreeMask(grid);
  return cv::floodFill(free, StartCell(grid, start), cv::Scalar(128), nullptr, cv::Scalar(),
                       cv::Scalar(), 4);
}

struct PassageStats {
  int components = 0;     // 8-connected pieces of the eroded free space
  double coverage = 0.0;  // share of the free cells a disk centred in it sweeps
};

// Where a disk of `radius_m` fits (erosion) and what it sweeps (dilation):
// a door narrower than the disk splits the eroded space.
PassageStats Passage(const OccupancyGrid& grid, double radius_m) {
  const int radius = static_cast<int>(std::lround(radius_m / grid.resolution_m()));
  const cv::Mat disk =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * radius + 1, 2 * radius + 1});
  const cv::Mat free = FreeMask(grid);
  cv::Mat eroded, swept, labels;
  cv::erode(free, eroded, disk, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::dilate(eroded, swept, disk);
  PassageStats stats;
  stats.components = cv::connectedComponents(eroded, labels, 8) - 1;
  stats.coverage = double(cv::countNonZero(swept & free)) / cv::countNonZero(free);
  return stats;
}

// Holes in the free space at least `min_size_m` across: obstacles a loop goes around.
int LoopHoles(const OccupancyGrid& grid, double min_size_m) {
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(FreeMask(grid), contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  const double min_cells = min_size_m / grid.resolution_m();
  int holes = 0;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    const bool is_hole = hierarchy[i][3] >= 0;
    const cv::Rect box = cv::boundingRect(contours[i]);
    if (is_hole && box.width >= min_cells && box.height >= min_cells) ++holes;
  }
  return holes;
}

// The shortest run of blocked cells with free cells at both ends, along rows
// and columns: walls and furniture between two free places.
int ThinnestSolidRun(const OccupancyGrid& grid) {
  int thinnest = std::numeric_limits<int>::max();
  const auto scan = [&](int count, auto free_at) {
    int last_free = -1;
    for (int i = 0; i < count; ++i) {
      if (!free_at(i)) continue;
      if (last_free >= 0 && i - last_free > 1) thinnest = std::min(thinnest, i - last_free - 1);
      last_free = i;
    }
  };
  for (int row = 0; row < grid.height_cells(); ++row) {
    scan(grid.width_cells(), [&](int col) { return grid.at({col, row}) == OccupancyGrid::kFree; });
  }
  for (int col = 0; col < grid.width_cells(); ++col) {
    scan(grid.height_cells(), [&](int row) { return grid.at({col, row}) == OccupancyGrid::kFree; });
  }
  return thinnest;
}

// Distance from the start to the nearest blocked cell's edge.
double StartClearance(const OccupancyGrid& grid, const Pose2d& start) {
  cv::Mat distance;
  cv::distanceTransform(FreeMask(grid), distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return (distance.at<float>(StartCell(grid, start)) - 0.5) * grid.resolution_m();
}

// What a generated world promises the robot. Office styles: a 0.9 m wide disk moves through
// one connected region and sweeps 90 % of the free area, walls are at least 0.15 m thick.
// Cluttered styles: a 0.5 m wide disk (the Kobuki-size robot's path) and 80 %, since legs
// and speckle may be single cells.
enum class Drivable { kOffice, kCluttered };

void ExpectDrivableWorld(const OccupancyGrid& grid, const Pose2d& start, const std::string& what,
                         Drivable kind = Drivable::kOffice) {
  SCOPED_TRACE(what);
  const bool office = kind == Drivable::kOffice;
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(grid.resolution_m(), 0.05);
  EXPECT_EQ(ReachableCells(grid, start), cv::countNonZero(FreeMask(grid)))
      << "free cells the start cannot reach";
  const PassageStats passage = Passage(grid, office ? 0.45 : 0.25);
  EXPECT_EQ(passage.components, 1) << "a gap narrower than the disk cuts the free space";
  EXPECT_GE(passage.coverage, office ? 0.9 : 0.8);
  if (office) {
    EXPECT_GE(ThinnestSolidRun(grid), 3) << "a wall thinner than 0.15 m";
  }
  EXPECT_GE(StartClearance(grid, start), 0.6);
  EXPECT_GE(LoopHoles(grid, kLoopObstacleMinSize_m), 1);
}

WorldgenOptions Options(WorldStyle style, double area_m2, uint64_t seed) {
  WorldgenOptions options = DefaultWorldgenOptions(style);
  options.target_free_area_m2 = area_m2;
  options.seed = seed;
  return options;
}

TEST(WorldgenTest, SameSeedSameMapOtherSeedOtherMap) {
  const GeneratedWorld a = GenerateWorld(Options(WorldStyle::kTest, 110.0, 7));
  const GeneratedWorld b = GenerateWorld(Options(WorldStyle::kTest, 110.0, 7));
  const GeneratedWorld c = GenerateWorld(Options(WorldStyle::kTest, 110.0, 8));
  EXPECT_EQ(a.grid.cells(), b.grid.cells());
  EXPECT_EQ(a.start.x_m, b.start.x_m);
  EXPECT_EQ(a.start.y_m, b.start.y_m);
  EXPECT_EQ(a.free_area_m2, b.free_area_m2);
  EXPECT_NE(a.grid.cells(), c.grid.cells());
}

TEST(WorldgenTest, FreeAreaMeetsTargetAndIsAllReachable) {
  const std::vector<std::pair<WorldStyle, double>> targets = {{WorldStyle::kTest, 90.0},
                                                              {WorldStyle::kTest, 140.0},
                                                              {WorldStyle::kOffice, 450.0},
                                                              {WorldStyle::kOffice, 741.0}};
  for (const auto& [style, target] : targets) {
    SCOPED_TRACE(WorldStyleName(style) + " " + std::to_string(target));
    const GeneratedWorld world = GenerateWorld(Options(style, target, 3));
    EXPECT_NEAR(world.free_area_m2, target, 0.03 * target);
    EXPECT_DOUBLE_EQ(world.free_area_m2, FreeArea(world.grid));
    EXPECT_EQ(ReachableCells(world.grid, world.start), cv::countNonZero(FreeMask(world.grid)));
  }
}

TEST(WorldgenTest, WorldsAreDrivableWithDoorsWallsLoopsAndClearStart) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const GeneratedWorld world = GenerateWorld(Options(WorldStyle::kTest, 110.0, seed));
    ExpectDrivableWorld(world.grid, world.start, "test seed " + std::to_string(seed));
    EXPECT_EQ(world.loop_count, 1);
    EXPECT_EQ(LoopHoles(world.grid, kLoopObstacleMinSize_m), 1);
  }
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedWorld world = GenerateWorld(Options(WorldStyle::kOffice, 741.0, seed));
    ExpectDrivableWorld(world.grid, world.start, "office seed " + std::to_string(seed));
    EXPECT_GE(world.room_count, 10);
  }
  const GeneratedWorld campus = GenerateWorld(Options(WorldStyle::kCampus, 2072.0, 5));
  ExpectDrivableWorld(campus.grid, campus.start, "campus seed 5");
  EXPECT_GE(LoopHoles(campus.grid, kLoopObstacleMinSize_m), 3);
}

TEST(WorldgenTest, CountLoopsCountsBlocksNotFurniture) {
  // A 10 x 10 m free square with a 4 x 4 m block and a 1 x 1 m table inside.
  OccupancyGrid grid(240, 240, 0.05, {0.0, 0.0}, OccupancyGrid::kUnknown);
  for (int row = 20; row < 220; ++row) {
    for (int col = 20; col < 220; ++col) grid.at({col, row}) = OccupancyGrid::kFree;
  }
  for (int row = 40; row < 120; ++row) {
    for (int col = 40; col < 120; ++col) grid.at({col, row}) = OccupancyGrid::kOccupied;
  }
  for (int row = 160; row < 180; ++row) {
    for (int col = 160; col < 180; ++col) grid.at({col, row}) = OccupancyGrid::kOccupied;
  }
  EXPECT_EQ(CountLoops(grid, 2.5), 1);
  EXPECT_EQ(CountLoops(grid, 0.5), 2);
  EXPECT_EQ(LoopHoles(grid, 2.5), 1);
}

TEST(WorldgenTest, BadOptionsNameTheOption) {
  WorldgenOptions options = Options(WorldStyle::kOffice, 741.0, 1);
  options.door_width_min_m = 0.6;
  try {
    GenerateWorld(options);
    FAIL() << "narrow doors accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("door_width_min_m = 0.6"), std::string::npos) << e.what();
  }
  // The office's 0.9 m furniture passage does not fit through 0.8 m doors.
  options.door_width_min_m = 0.8;
  try {
    GenerateWorld(options);
    FAIL() << "a passage wider than the doors accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("passage_width_m = 0.9"), std::string::npos) << e.what();
  }
  for (const auto& [name, set] :
       std::vector<std::pair<std::string, std::function<void(WorldgenOptions&)>>>{
           {"clutter_fill = 1.5", [](WorldgenOptions& o) { o.clutter_fill = 1.5; }},
           {"speckle_per_m2 = -1", [](WorldgenOptions& o) { o.speckle_per_m2 = -1.0; }},
           {"ragged_edge_probability = 2",
            [](WorldgenOptions& o) { o.ragged_edge_probability = 2; }},
           {"robot_width_m = 0.8", [](WorldgenOptions& o) { o.robot_width_m = 0.8; }},
           {"hall_door_spacing_m = 2", [](WorldgenOptions& o) { o.hall_door_spacing_m = 2.0; }}}) {
    WorldgenOptions bad = Options(WorldStyle::kClutteredOffice, 400.0, 1);
    set(bad);
    try {
      GenerateWorld(bad);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(GenerateWorld(Options(WorldStyle::kOffice, -5.0, 1)), std::invalid_argument);
  EXPECT_THROW(ParseWorldStyle("castle"), std::invalid_argument);
  // Smaller than the smallest ring of corridors around one room.
  EXPECT_THROW(GenerateWorld(Options(WorldStyle::kTest, 5.0, 1)), std::runtime_error);
}

TEST(WorldgenTest, WrittenWorldLoadsAsFolderWorldYamlAndBareMap) {
  const WorldgenOptions options = Options(WorldStyle::kTest, 100.0, 11);
  const GeneratedWorld world = GenerateWorld(options);
  const std::string out = TestTempPath("tiny");
  WriteWorld(world, options, "tiny", out, RegenerateCommand(options, "tiny", out));
  for (const char* file : {"map.yaml", "map.pgm", "world.yaml", "README.md"}) {
    EXPECT_TRUE(fs::is_regular_file(fs::path(out) / file)) << file;
  }

  for (const std::string& path : {out, out + "/world.yaml"}) {
    SCOPED_TRACE(path);
    const WorldInfo info = LoadWorld(path);
    EXPECT_TRUE(info.has_start);
    EXPECT_NEAR(info.start.x_m, world.start.x_m, 1e-6);
    EXPECT_NEAR(info.start.y_m, world.start.y_m, 1e-6);
    EXPECT_NEAR(info.start.yaw_rad, world.start.yaw_rad, 1e-6);
    EXPECT_NEAR(info.free_area_m2, world.free_area_m2, 1e-6);
    EXPECT_EQ(fs::path(info.map_yaml_path), fs::path(out) / "map.yaml");
    EXPECT_EQ(info.map.grid.cells(), world.grid.cells());
  }
  const WorldInfo bare = LoadWorld(out + "/map.yaml");
  EXPECT_FALSE(bare.has_start);
  EXPECT_TRUE(bare.world_yaml_path.empty());
  EXPECT_NEAR(bare.free_area_m2, world.free_area_m2, 1e-6);

  const YAML::Node yaml = YAML::LoadFile(out + "/world.yaml");
  EXPECT_EQ(yaml["generator"]["command"].as<std::string>(),
            "aslam-worldgen --out " + out + " --style test --free-area 100 --seed 11 --name tiny");
  EXPECT_EQ(yaml["generator"]["seed"].as<uint64_t>(), 11u);
  EXPECT_EQ(yaml["rooms"].as<int>(), world.room_count);
}

TEST(WorldgenTest, LoadWorldErrorsNameFileAndKey) {
  const WorldgenOptions options = Options(WorldStyle::kTest, 100.0, 11);
  const std::string out = TestTempPath("w");
  WriteWorld(GenerateWorld(options), options, "w", out, "n/a");
  const std::string world_yaml = out + "/world.yaml";
  const auto error_of = [&](const std::string& text) {
    std::ofstream(world_yaml) << text;
    try {
      LoadWorld(out);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string message = error_of("free_area_m2: 100\n");
  EXPECT_NE(message.find(world_yaml + ": missing key 'start'"), std::string::npos) << message;
  message = error_of("start: {x_m: 1, y_m: 1}\nfree_area_m2: 100\n");
  EXPECT_NE(message.find("missing key 'start.yaw_rad'"), std::string::npos) << message;
  message = error_of("start: {x_m: wide, y_m: 1, yaw_rad: 0}\nfree_area_m2: 100\n");
  EXPECT_NE(message.find("key 'start.x_m': expected a number, got 'wide'"), std::string::npos)
      << message;
  message = error_of("start: {x_m: -0.5, y_m: -0.5, yaw_rad: 0}\nfree_area_m2: 100\n");
  EXPECT_NE(message.find("key 'start': (-0.5, -0.5) is not a free cell"), std::string::npos)
      << message;
  message = error_of("start: {x_m: 1, y_m: [1\nfree_area_m2: 100\n");
  EXPECT_NE(message.find(world_yaml + ":"), std::string::npos) << message;
  EXPECT_NE(message.find("malformed YAML"), std::string::npos) << message;
  message = error_of("start: {x_m: 1, y_m: 1, yaw_rad: 0}\nfree_area_m2: 100\nmap: gone.yaml\n");
  EXPECT_NE(message.find("gone.yaml: map file not found"), std::string::npos) << message;

  EXPECT_THROW(LoadWorld(TestTempPath("nowhere")), std::runtime_error);
  fs::create_directories(TestTempPath("empty"));
  EXPECT_THROW(LoadWorld(TestTempPath("empty")), std::runtime_error);
}

// The worlds shipped in the repository: documented sizes, drivable, and
// exactly what their recorded command regenerates.
struct ShippedWorld {
  const char* name;
  double documented_free_area_m2;  // 0: only the bound below applies
  double max_free_area_m2;
  int min_loops;
  bool cluttered = false;  // checked with the cluttered styles' passage rule
};

void PrintTo(const ShippedWorld& world, std::ostream* os) { *os << world.name; }

class ShippedWorldTest : public ::testing::TestWithParam<ShippedWorld> {};

TEST_P(ShippedWorldTest, LoadsWithDocumentedAreaAndRegenerates) {
  const ShippedWorld& shipped = GetParam();
  const std::string dir = std::string(ASLAM_SOURCE_DIR) + "/worlds/" + shipped.name;
  const WorldInfo info = LoadWorld(dir);
  ASSERT_TRUE(info.has_start);
  const OccupancyGrid& grid = info.map.grid;
  EXPECT_NEAR(FreeArea(grid), info.free_area_m2, 1e-6);
  if (shipped.documented_free_area_m2 > 0.0) {
    EXPECT_NEAR(info.free_area_m2, shipped.documented_free_area_m2,
                0.03 * shipped.documented_free_area_m2);
  }
  EXPECT_LT(info.free_area_m2, shipped.max_free_area_m2);
  if (shipped.cluttered) {
    ExpectDrivableWorld(grid, info.start, shipped.name, Drivable::kCluttered);
  } else {
    ExpectDrivableWorld(grid, info.start, shipped.name);
  }
  EXPECT_GE(LoopHoles(grid, kLoopObstacleMinSize_m), shipped.min_loops);

  const YAML::Node generator = YAML::LoadFile(dir + "/world.yaml")["generator"];
  WorldgenOptions options =
      DefaultWorldgenOptions(ParseWorldStyle(generator["style"].as<std::string>()));
  options.seed = generator["seed"].as<uint64_t>();
  options.target_free_area_m2 = generator["target_free_area_m2"].as<double>();
  EXPECT_EQ(generator["command"].as<std::string>(),
            RegenerateCommand(options, shipped.name, std::string("worlds/") + shipped.name));
  const GeneratedWorld regenerated = GenerateWorld(options);
  EXPECT_EQ(regenerated.grid.cells(), grid.cells())
      << "regenerate with: " << generator["command"].as<std::string>();
  EXPECT_EQ(regenerated.grid.origin_m().x_m, grid.origin_m().x_m);
  EXPECT_EQ(regenerated.grid.origin_m().y_m, grid.origin_m().y_m);
}

INSTANTIATE_TEST_SUITE_P(
    Worlds, ShippedWorldTest,
    ::testing::Values(ShippedWorld{"campus", 2072.0, 2200.0, 3},
                      ShippedWorld{"office", 741.0, 800.0, 1}, ShippedWorld{"test", 0.0, 150.0, 1},
                      ShippedWorld{"cluttered_office", 1500.0, 1600.0, 1, true},
                      ShippedWorld{"warehouse_floor", 2500.0, 2700.0, 1, true}),
    [](const auto& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------
// The cluttered styles, measured on the map.

// Generated once per style: each takes about a second.
const GeneratedWorld& ClutteredOffice() {
  static const GeneratedWorld world =
      GenerateWorld(Options(WorldStyle::kClutteredOffice, 1500.0, 2));
  return world;
}

const GeneratedWorld& Warehouse() {
  static const GeneratedWorld world = GenerateWorld(Options(WorldStyle::kWarehouse, 2500.0, 2));
  return world;
}

cv::Mat OccupiedMask(const OccupancyGrid& grid) {
  const cv::Mat cells(grid.height_cells(), grid.width_cells(), CV_8S,
                      const_cast<int8_t*>(grid.cells().data()));
  return cells == OccupancyGrid::kOccupied;
}

// Occupied pieces of at most `max_cells` cells: legs and speckle.
struct SmallObstacle {
  cv::Rect box;
  bool isolated;  // nothing else occupied within 3 cells (0.15 m) of it
};

std::vector<SmallObstacle> SmallObstacles(const OccupancyGrid& grid, int max_cells) {
  const cv::Mat occupied = OccupiedMask(grid);
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(occupied, labels, stats, centroids, 8);
  std::vector<SmallObstacle> small;
  for (int label = 1; label < count; ++label) {
    if (stats.at<int>(label, cv::CC_STAT_AREA) > max_cells) continue;
    const cv::Rect box(
        stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
        stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    const cv::Rect ring = cv::Rect(box.x - 3, box.y - 3, box.width + 6, box.height + 6) &
                          cv::Rect({}, occupied.size());
    small.push_back({box, cv::countNonZero(occupied(ring)) == cv::countNonZero(occupied(box))});
  }
  return small;
}

TEST(ClutteredWorldgenTest, StylesMeetTheirAreaAndStayDrivableForTheRobot) {
  for (const GeneratedWorld* world : {&ClutteredOffice(), &Warehouse()}) {
    const double target = world == &ClutteredOffice() ? 1500.0 : 2500.0;
    SCOPED_TRACE(target);
    EXPECT_NEAR(world->free_area_m2, target, 0.03 * target);
    EXPECT_DOUBLE_EQ(world->free_area_m2, FreeArea(world->grid));
    ExpectDrivableWorld(world->grid, world->start, "cluttered", Drivable::kCluttered);
    EXPECT_GE(world->room_count, 15);
  }
}

TEST(ClutteredWorldgenTest, RoomDoorsAreNarrowAndHallDoorsTwiceThat) {
  const GeneratedWorld& world = ClutteredOffice();
  const OccupancyGrid& grid = world.grid;
  int room_doors = 0, measured = 0;
  for (const DoorOpening& door : world.doors) {
    const CellIndex centre = grid.WorldToCell({door.x_m, door.y_m});
    if (grid.at(centre) != OccupancyGrid::kFree) continue;  // in a pocket filled solid
    // The free run along the wall through the door's centre: the opening.
    const int step_col = door.wall_along_x ? 1 : 0, step_row = door.wall_along_x ? 0 : 1;
    int run = 1;
    for (int sign : {-1, 1}) {
      for (CellIndex cell{centre.col + sign * step_col, centre.row + sign * step_row};
           grid.at(cell) == OccupancyGrid::kFree;
           cell = {cell.col + sign * step_col, cell.row + sign * step_row}) {
        ++run;
      }
    }
    const double width_m = run * grid.resolution_m();
    ++measured;
    if (width_m <= 0.9 + 1e-9) {
      EXPECT_GE(width_m, 0.7 - 1e-9) << "door at " << door.x_m << ", " << door.y_m;
      ++room_doors;
    } else {
      EXPECT_GE(width_m, 1.4 - 1e-9) << "door at " << door.x_m << ", " << door.y_m;
      EXPECT_LE(width_m, 1.8 + 1e-9) << "door at " << door.x_m << ", " << door.y_m;
    }
  }
  EXPECT_GE(measured, 30);
  EXPECT_GE(room_doors, 0.7 * measured);
}

TEST(ClutteredWorldgenTest, FurnitureCoversItsShareOfTheRooms) {
  for (const GeneratedWorld* world : {&ClutteredOffice(), &Warehouse()}) {
    const OccupancyGrid& grid = world->grid;
    ASSERT_EQ(world->furniture_cells.size(), grid.cells().size());
    int furniture = 0, furniture_not_occupied = 0;
    for (std::size_t i = 0; i < grid.cells().size(); ++i) {
      if (!world->furniture_cells[i]) continue;
      ++furniture;
      if (grid.cells()[i] != OccupancyGrid::kOccupied) ++furniture_not_occupied;
    }
    EXPECT_EQ(furniture_not_occupied, 0);
    EXPECT_NEAR(furniture * 0.05 * 0.05, world->furniture_area_m2, 1e-6);
    EXPECT_LE(world->furniture_area_m2, world->furniture_footprint_m2);
    // clutter_fill 0.22 (office) and 0.2 (warehouse), scaled by room kind
    // between 0.8 and 1.1, and by what fits; warehouse shelving adds more.
    const double share = world->furniture_footprint_m2 / world->room_floor_area_m2;
    EXPECT_GE(share, 0.12);
    EXPECT_LE(share, 0.35);
  }
}

TEST(ClutteredWorldgenTest, TablesAndChairsStandOnLegs) {
  const std::vector<SmallObstacle> small = SmallObstacles(ClutteredOffice().grid, 4);
  std::vector<cv::Rect> legs;
  for (const SmallObstacle& obstacle : small) {
    if (obstacle.isolated && obstacle.box.width <= 2 && obstacle.box.height <= 2) {
      legs.push_back(obstacle.box);
    }
  }
  EXPECT_GE(legs.size(), 40u);
  // Legs stand in rectangles: most have another leg in the same row or
  // column 0.3-2.5 m away.
  int paired = 0;
  for (const cv::Rect& leg : legs) {
    for (const cv::Rect& other : legs) {
      const int dx = std::abs(other.x - leg.x), dy = std::abs(other.y - leg.y);
      if ((dx == 0 && dy >= 6 && dy <= 50) || (dy == 0 && dx >= 6 && dx <= 50)) {
        ++paired;
        break;
      }
    }
  }
  EXPECT_GE(paired, 0.7 * legs.size());
}

// Straight pieces of the free space's outline (polygon edges within 1.5
// cells of it): the count of short ones (<= 0.15 m, steps of a ragged wall)
// and of long ones at a slope (>= 1 m, 15 to 75 degrees off the axes).
struct OutlineStats {
  int short_steps = 0;
  int angled = 0;
};

OutlineStats Outline(const OccupancyGrid& grid) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(FreeMask(grid), contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  OutlineStats stats;
  for (const auto& contour : contours) {
    std::vector<cv::Point> polygon;
    cv::approxPolyDP(contour, polygon, 1.5, true);
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const cv::Point d = polygon[(i + 1) % polygon.size()] - polygon[i];
      const double length_m = std::hypot(d.x, d.y) * grid.resolution_m();
      const double degrees = std::atan2(std::abs(d.y), std::abs(d.x)) * 180.0 / M_PI;
      if (length_m >= 1.0 && degrees >= 15.0 && degrees <= 75.0) ++stats.angled;
      if (length_m <= 0.15) ++stats.short_steps;
    }
  }
  return stats;
}

TEST(ClutteredWorldgenTest, MapHasSpeckleRaggedAndAngledWalls) {
  // The clean office map for comparison: straight walls, no speckle.
  const OccupancyGrid office = LoadWorld(std::string(ASLAM_SOURCE_DIR) + "/worlds/office").map.grid;
  const OutlineStats clean = Outline(office);
  EXPECT_EQ(clean.angled, 0);
  const double clean_steps_per_m2 = clean.short_steps / FreeArea(office);
  for (const GeneratedWorld* world : {&ClutteredOffice(), &Warehouse()}) {
    const OccupancyGrid& grid = world->grid;
    // Speckle: one- or two-cell obstacles alone in free space.
    int speckle = 0;
    const cv::Mat free = FreeMask(grid);
    for (const SmallObstacle& obstacle : SmallObstacles(grid, 2)) {
      const cv::Rect ring(obstacle.box.x - 1, obstacle.box.y - 1, obstacle.box.width + 2,
                          obstacle.box.height + 2);
      if (cv::countNonZero(free(ring)) == ring.area() - cv::countNonZero(~free(obstacle.box))) {
        ++speckle;
      }
    }
    EXPECT_GE(speckle, 0.05 * world->free_area_m2);

    const OutlineStats outline = Outline(grid);
    EXPECT_GE(outline.angled, 1) << "no wall at a slope";
    EXPECT_GE(outline.short_steps / world->free_area_m2, 3.0 * clean_steps_per_m2)
        << "walls no more ragged than the clean office's";
  }
}

TEST(ClutteredWorldgenTest, SameSeedSameMapOtherSeedOtherMap) {
  for (const auto& [style, area_m2] : std::vector<std::pair<WorldStyle, double>>{
           {WorldStyle::kClutteredOffice, 500.0}, {WorldStyle::kWarehouse, 900.0}}) {
    const GeneratedWorld a = GenerateWorld(Options(style, area_m2, 7));
    const GeneratedWorld b = GenerateWorld(Options(style, area_m2, 7));
    const GeneratedWorld c = GenerateWorld(Options(style, area_m2, 8));
    EXPECT_EQ(a.grid.cells(), b.grid.cells());
    EXPECT_EQ(a.start.x_m, b.start.x_m);
    EXPECT_EQ(a.furniture_cells, b.furniture_cells);
    EXPECT_NE(a.grid.cells(), c.grid.cells());
    ExpectDrivableWorld(a.grid, a.start, WorldStyleName(style), Drivable::kCluttered);
  }
}

// The real maps from navigation2: they load, their start is free with
// clearance, and world.yaml's free area is what the start reaches.
TEST(RealMapTest, DepotAndWarehouseLoadWithTheirStartAndFreeArea) {
  for (const auto& [name, resolution_m] :
       std::vector<std::pair<std::string, double>>{{"depot", 0.05}, {"warehouse", 0.03}}) {
    SCOPED_TRACE(name);
    const std::string dir = std::string(ASLAM_SOURCE_DIR) + "/worlds/" + name;
    const WorldInfo info = LoadWorld(dir);
    ASSERT_TRUE(info.has_start);
    const OccupancyGrid& grid = info.map.grid;
    EXPECT_EQ(grid.resolution_m(), resolution_m);
    EXPECT_EQ(grid.at(grid.WorldToCell({info.start.x_m, info.start.y_m})), OccupancyGrid::kFree);
    EXPECT_GE(StartClearance(grid, info.start), 0.3);
    const double reachable_m2 =
        ReachableCells(grid, info.start) * grid.resolution_m() * grid.resolution_m();
    EXPECT_NEAR(info.free_area_m2, reachable_m2, 0.01);
    EXPECT_LE(reachable_m2, FreeArea(grid) + 1e-6);
    for (const char* file : {"LICENSE", "README.md", "map.pgm", "map.yaml"}) {
      EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / file)) << file;
    }
  }
}

// The command line tool: usage, flag errors (exit 1), and a world written.
int RunWorldgen(const std::string& arguments) {
  const std::string command =
      std::string(ASLAM_WORLDGEN_BIN) + " " + arguments + " > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(WorldgenMainTest, FlagsAndExitCodes) {
  const std::string out = TestTempPath("cli");
  EXPECT_EQ(RunWorldgen("--help"), 0);
  EXPECT_EQ(RunWorldgen("--bogus 1"), 1);
  EXPECT_EQ(RunWorldgen("--free-area 100 --seed 1"), 1);                    // no --out
  EXPECT_EQ(RunWorldgen("--out " + out + " --free-area big --seed 1"), 1);  // not a number
  EXPECT_EQ(RunWorldgen("--out " + out + " --free-area 100 --seed -1"), 1);
  EXPECT_EQ(RunWorldgen("--out " + out + " --free-area 100 --seed 1 --style castle"), 1);
  EXPECT_EQ(RunWorldgen("--out " + out + " --free-area 100 --seed 1 stray"), 1);
  EXPECT_EQ(RunWorldgen("--out " + out + " --free-area"), 1);
  EXPECT_FALSE(fs::exists(out));

  EXPECT_EQ(RunWorldgen("--out " + out + " --style test --free-area=100 --seed 4"), 0);
  const WorldInfo info = LoadWorld(out);
  EXPECT_NEAR(info.free_area_m2, 100.0, 3.0);
  const YAML::Node yaml = YAML::LoadFile(out + "/world.yaml");
  EXPECT_EQ(yaml["name"].as<std::string>(), "cli");
}

}  // namespace
}  // namespace aslam
