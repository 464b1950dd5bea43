#include "worlds/worldgen.h"
#include "common/test_temp_dir.h"
#include "common/world_file.h"

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

void ExpectDrivableOfficeWorld(const OccupancyGrid& grid, const Pose2d& start,
                               const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(grid.resolution_m(), 0.05);
  EXPECT_EQ(ReachableCells(grid, start), cv::countNonZero(FreeMask(grid)))
      << "free cells the start cannot reach";
  const PassageStats passage = Passage(grid, 0.45);
  EXPECT_EQ(passage.components, 1) << "a door or gap narrower than 0.9 m cuts the free space";
  EXPECT_GE(passage.coverage, 0.9);
  EXPECT_GE(ThinnestSolidRun(grid), 3) << "a wall thinner than 0.15 m";
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
    ExpectDrivableOfficeWorld(world.grid, world.start, "test seed " + std::to_string(seed));
    EXPECT_EQ(world.loop_count, 1);
    EXPECT_EQ(LoopHoles(world.grid, kLoopObstacleMinSize_m), 1);
  }
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedWorld world = GenerateWorld(Options(WorldStyle::kOffice, 741.0, seed));
    ExpectDrivableOfficeWorld(world.grid, world.start, "office seed " + std::to_string(seed));
    EXPECT_GE(world.room_count, 10);
  }
  const GeneratedWorld campus = GenerateWorld(Options(WorldStyle::kCampus, 2072.0, 5));
  ExpectDrivableOfficeWorld(campus.grid, campus.start, "campus seed 5");
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
  options.door_width_min_m = 0.8;
  try {
    GenerateWorld(options);
    FAIL() << "narrow doors accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("door_width_min_m = 0.8"), std::string::npos) << e.what();
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
  ExpectDrivableOfficeWorld(grid, info.start, shipped.name);
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

INSTANTIATE_TEST_SUITE_P(Worlds, ShippedWorldTest,
                         ::testing::Values(ShippedWorld{"campus", 2072.0, 2200.0, 3},
                                           ShippedWorld{"office", 741.0, 800.0, 1},
                                           ShippedWorld{"test", 0.0, 150.0, 1}),
                         [](const auto& info) { return std::string(info.param.name); });

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
