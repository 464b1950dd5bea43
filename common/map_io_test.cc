#include "common/map_io.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/test_temp_dir.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

// Files go in the test case's own folder.
class MapIoTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  void WriteText(const std::string& name, const std::string& text) const {
    std::ofstream out(Path(name));
    out << text;
  }

  // A binary PGM written byte by byte, so the loader is checked against
  // pixels we chose rather than against OpenCV's writer. Rows top to bottom.
  void WritePgm(const std::string& name, const std::vector<std::vector<uint8_t>>& rows) const {
    std::ofstream out(Path(name), std::ios::binary);
    out << "P5\n" << rows[0].size() << " " << rows.size() << "\n255\n";
    for (const auto& row : rows) {
      out.write(reinterpret_cast<const char*>(row.data()),
                static_cast<std::streamsize>(row.size()));
    }
  }

  // The message of the MapFileError LoadMap throws, or "" if it does not throw.
  std::string LoadError(const std::string& yaml_name) const {
    try {
      LoadMap(Path(yaml_name));
    } catch (const MapFileError& e) {
      return e.what();
    }
    return "";
  }

  void WriteYaml(const std::string& name, const std::string& body) const { WriteText(name, body); }

  const fs::path dir_ = TestTempDir();
};

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)

OccupancyGrid MakeTrinaryGrid() {
  OccupancyGrid grid(7, 5, 0.05, {-12.5, 3.25});
  for (int row = 0; row < grid.height_cells(); ++row) {
    for (int col = 0; col < grid.width_cells(); ++col) {
      const int pattern = (col + 2 * row) % 3;
      grid.at({col, row}) = pattern == 0   ? OccupancyGrid::kFree
                            : pattern == 1 ? OccupancyGrid::kOccupied
                                           : OccupancyGrid::kUnknown;
    }
  }
  grid.at({0, 0}) = OccupancyGrid::kOccupied;  // marks the bottom-left corner
  grid.at({6, 4}) = OccupancyGrid::kFree;      // and the top-right one
  return grid;
}

void ExpectSameGrid(const OccupancyGrid& expected, const OccupancyGrid& actual) {
  ASSERT_EQ(expected.width_cells(), actual.width_cells());
  ASSERT_EQ(expected.height_cells(), actual.height_cells());
  EXPECT_EQ(expected.resolution_m(), actual.resolution_m());
  EXPECT_EQ(expected.origin_m().x_m, actual.origin_m().x_m);
  EXPECT_EQ(expected.origin_m().y_m, actual.origin_m().y_m);
  EXPECT_EQ(expected.cells(), actual.cells());
}

TEST_F(MapIoTest, RoundTripPgmIsExact) {
  const OccupancyGrid grid = MakeTrinaryGrid();
  SaveMap(grid, Path("map"), MapImageFormat::kPgm);
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  ExpectSameGrid(grid, loaded.grid);
  EXPECT_EQ(loaded.metadata.image, "map.pgm");
  EXPECT_EQ(fs::path(loaded.image_path), dir_ / "map.pgm");
  EXPECT_EQ(loaded.metadata.mode, MapMode::kTrinary);
  EXPECT_FALSE(loaded.metadata.negate);
  EXPECT_EQ(loaded.metadata.occupied_thresh, 0.65);
  EXPECT_EQ(loaded.metadata.free_thresh, 0.196);

  // map_saver pixel values, image row 0 at the top of the map.
  const cv::Mat image = cv::imread(Path("map.pgm"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8UC1);
  EXPECT_EQ(image.at<uint8_t>(4, 0), 0);    // grid (0, 0): occupied marker
  EXPECT_EQ(image.at<uint8_t>(0, 6), 254);  // grid (6, 4): free marker
  EXPECT_EQ(image.at<uint8_t>(4, 1), 0);    // grid (1, 0): occupied
  EXPECT_EQ(image.at<uint8_t>(4, 2), 205);  // grid (2, 0): unknown
  EXPECT_EQ(image.at<uint8_t>(4, 3), 254);  // grid (3, 0): free
}

TEST_F(MapIoTest, RoundTripPngIsExact) {
  const OccupancyGrid grid = MakeTrinaryGrid();
  SaveMap(grid, Path("map"), MapImageFormat::kPng);
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  ExpectSameGrid(grid, loaded.grid);
  EXPECT_EQ(loaded.metadata.image, "map.png");
}

TEST_F(MapIoTest, SaveThresholdsIntermediateValues) {
  OccupancyGrid grid(4, 1, 0.1, {0.0, 0.0});
  grid.mutable_cells() = {19, 20, 64, 65};
  SaveMap(grid, Path("map"));
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  EXPECT_EQ(loaded.grid.cells(), (std::vector<int8_t>{0, -1, -1, 100}));
}

TEST_F(MapIoTest, SaveToMissingDirectoryThrows) {
  EXPECT_THROW(SaveMap(MakeTrinaryGrid(), Path("no/such/dir/map")), MapFileError);
}

// Pixels (top row first) and the cells they must become (bottom row first).
const std::vector<std::vector<uint8_t>> kHandMadePixels = {
    {0, 254, 205, 50},     // top image row
    {255, 100, 180, 89}};  // bottom image row

TEST_F(MapIoTest, HandMadePgmTrinaryFlipsRows) {
  WritePgm("img.pgm", kHandMadePixels);
  WriteYaml("map.yaml",
            "image: img.pgm\nresolution: 0.1\norigin: [1.0, -2.0, 0.0]\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n");
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  ASSERT_EQ(loaded.grid.width_cells(), 4);
  ASSERT_EQ(loaded.grid.height_cells(), 2);
  // p = (255 - v) / 255: 255 -> 0 free; 100 -> 0.61 unknown; 180 -> 0.29 unknown;
  // 89 -> 0.651 occupied; 0 -> 1 occupied; 254 -> 0.004 free;
  // 205 -> 0.19608 (not below 0.196) unknown; 50 -> 0.80 occupied.
  const std::vector<int8_t> expected = {0,   -1, -1, 100,   // grid row 0 = bottom image row
                                        100, 0,  -1, 100};  // grid row 1 = top image row
  EXPECT_EQ(loaded.grid.cells(), expected);
  EXPECT_EQ(loaded.grid.origin_m().x_m, 1.0);
  EXPECT_EQ(loaded.grid.origin_m().y_m, -2.0);
  EXPECT_EQ(loaded.grid.resolution_m(), 0.1);
}

TEST_F(MapIoTest, HandMadePgmNegate) {
  WritePgm("img.pgm", kHandMadePixels);
  WriteYaml("map.yaml", "image: img.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 1\n");
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  // p = v / 255: 255 -> 1 occupied; 100 -> 0.39 unknown; 180 -> 0.71 occupied;
  // 89 -> 0.35 unknown; 0 -> 0 free; 254 -> 0.996 occupied; 205 -> 0.80 occupied;
  // 50 -> 0.19608 unknown.
  const std::vector<int8_t> expected = {100, -1,  100, -1,   // bottom image row
                                        0,   100, 100, -1};  // top image row
  EXPECT_EQ(loaded.grid.cells(), expected);
  EXPECT_TRUE(loaded.metadata.negate);
}

TEST_F(MapIoTest, HandMadePgmScaleMode) {
  WritePgm("img.pgm", {{0, 153, 102}, {255, 230, 30}});
  WriteYaml("map.yaml",
            "image: img.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: scale\n"
            "occupied_thresh: 0.8\nfree_thresh: 0.2\n");
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  // In between, map_server's 1 + 98 * (p - free) / (occ - free), truncated:
  // 153 -> p 0.4 -> 1 + 98/3 = 33.7 -> 33; 102 -> p 0.6 -> 1 + 196/3 = 66.3 -> 66.
  // Outside: 0 -> 100, 255 -> 0, 230 (p 0.098) -> 0, 30 (p 0.88) -> 100.
  const std::vector<int8_t> expected = {0,   0,  100,  // bottom image row
                                        100, 33, 66};  // top image row
  EXPECT_EQ(loaded.grid.cells(), expected);
  EXPECT_EQ(loaded.metadata.mode, MapMode::kScale);
}

TEST_F(MapIoTest, HandMadePgmRawMode) {
  WritePgm("img.pgm", {{0, 37, 100, 101, 255}});
  WriteYaml("map.yaml", "image: img.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: raw\n");
  const LoadedMap loaded = LoadMap(Path("map.yaml"));
  // The pixel is the cell value; bytes above 100 are not occupancies: unknown.
  EXPECT_EQ(loaded.grid.cells(), (std::vector<int8_t>{0, 37, 100, -1, -1}));
}

TEST_F(MapIoTest, ImagePathRelativeToYamlFolderOrAbsolute) {
  fs::create_directories(dir_ / "maps" / "images");
  WritePgm("maps/images/img.pgm", {{0, 255}});
  WriteYaml("maps/relative.yaml", "image: images/img.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  WriteYaml("absolute.yaml",
            "image: " + Path("maps/images/img.pgm") + "\nresolution: 0.05\norigin: [0, 0, 0]\n");
  const LoadedMap relative = LoadMap(Path("maps/relative.yaml"));
  EXPECT_EQ(fs::path(relative.image_path), dir_ / "maps" / "images" / "img.pgm");
  EXPECT_EQ(relative.grid.cells(), (std::vector<int8_t>{100, 0}));
  const LoadedMap absolute = LoadMap(Path("absolute.yaml"));
  EXPECT_EQ(absolute.grid.cells(), (std::vector<int8_t>{100, 0}));
}

TEST_F(MapIoTest, MissingYamlNamesTheFile) {
  const std::string message = LoadError("nope.yaml");
  EXPECT_CONTAINS(message, Path("nope.yaml"));
  EXPECT_CONTAINS(message, "not found");
}

TEST_F(MapIoTest, MalformedYamlNamesFileAndLine) {
  WriteYaml("map.yaml", "image: img.pgm\norigin: [0, 0\nresolution: 0.05\n");
  const std::string message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, Path("map.yaml") + ":");
  EXPECT_CONTAINS(message, "malformed YAML");
  EXPECT_CONTAINS(message, ":3:");  // the parser notices at the line after the open list
}

TEST_F(MapIoTest, MissingImageFileNamesIt) {
  WriteYaml("map.yaml", "image: ghost.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  const std::string message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, Path("map.yaml"));
  EXPECT_CONTAINS(message, "key 'image'");
  EXPECT_CONTAINS(message, "ghost.pgm");
  EXPECT_CONTAINS(message, "not found");
}

TEST_F(MapIoTest, NonImageDataNamesTheImage) {
  WriteText("img.pgm", "this is plain text, not a picture\n");
  WriteYaml("map.yaml", "image: img.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  const std::string message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, Path("map.yaml"));
  EXPECT_CONTAINS(message, "key 'image'");
  EXPECT_CONTAINS(message, "img.pgm");
  EXPECT_CONTAINS(message, "not a readable");
}

TEST_F(MapIoTest, NonPositiveResolutionNamesKeyAndValue) {
  WritePgm("img.pgm", {{0}});
  for (const std::string value : {"-0.05", "0", "0.0"}) {
    WriteYaml("map.yaml", "image: img.pgm\nresolution: " + value + "\norigin: [0, 0, 0]\n");
    const std::string message = LoadError("map.yaml");
    EXPECT_CONTAINS(
        message,
        Path("map.yaml") + ": key 'resolution': expected a positive number, got '" + value + "'");
  }
  WriteYaml("map.yaml", "image: img.pgm\nresolution: fine\norigin: [0, 0, 0]\n");
  EXPECT_CONTAINS(LoadError("map.yaml"), "key 'resolution': expected a number, got 'fine'");
}

TEST_F(MapIoTest, ThresholdsOutOfRangeNameKeyAndValue) {
  WritePgm("img.pgm", {{0}});
  const std::string base = "image: img.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  WriteYaml("map.yaml", base + "occupied_thresh: 1.5\n");
  std::string message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, Path("map.yaml"));
  EXPECT_CONTAINS(message, "key 'occupied_thresh'");
  EXPECT_CONTAINS(message, "'1.5'");

  WriteYaml("map.yaml", base + "free_thresh: -0.1\n");
  message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, "key 'free_thresh'");
  EXPECT_CONTAINS(message, "'-0.1'");

  WriteYaml("map.yaml", base + "occupied_thresh: 0.5\nfree_thresh: 0.6\n");
  message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, "key 'free_thresh'");
  EXPECT_CONTAINS(message, "below occupied_thresh (0.5)");
  EXPECT_CONTAINS(message, "'0.6'");
}

TEST_F(MapIoTest, MissingRequiredKeyNamesIt) {
  WritePgm("img.pgm", {{0}});
  const std::vector<std::pair<std::string, std::string>> lines = {
      {"image", "image: img.pgm\n"},
      {"resolution", "resolution: 0.05\n"},
      {"origin", "origin: [0, 0, 0]\n"}};
  for (const auto& [missing_key, unused] : lines) {
    std::string body;
    for (const auto& [key, line] : lines) {
      if (key != missing_key) body += line;
    }
    WriteYaml("map.yaml", body);
    const std::string message = LoadError("map.yaml");
    EXPECT_CONTAINS(message, Path("map.yaml") + ": missing required key '" + missing_key + "'");
  }
}

TEST_F(MapIoTest, BadOriginModeAndNegateNameKeyAndValue) {
  WritePgm("img.pgm", {{0}});
  const std::string base = "image: img.pgm\nresolution: 0.05\n";
  WriteYaml("map.yaml", base + "origin: [0, 0, 0.5]\n");
  std::string message = LoadError("map.yaml");
  EXPECT_CONTAINS(message, "key 'origin'");
  EXPECT_CONTAINS(message, "yaw 0.5");

  WriteYaml("map.yaml", base + "origin: [0, 0]\n");
  EXPECT_CONTAINS(LoadError("map.yaml"), "key 'origin': expected [x, y, yaw]");

  WriteYaml("map.yaml", base + "origin: [0, 0, 0]\nmode: fancy\n");
  EXPECT_CONTAINS(LoadError("map.yaml"), "key 'mode': expected trinary, scale or raw, got 'fancy'");

  WriteYaml("map.yaml", base + "origin: [0, 0, 0]\nnegate: 2\n");
  EXPECT_CONTAINS(LoadError("map.yaml"), "key 'negate': expected 0 or 1, got '2'");
}

}  // namespace
}  // namespace aslam
