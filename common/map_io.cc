#include "common/map_io.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/atomic_file.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

// The pixel values map_saver writes.
constexpr uint8_t kFreePixel = 254;
constexpr uint8_t kOccupiedPixel = 0;
constexpr uint8_t kUnknownPixel = 205;
// Cell values at or below / at or above these are saved free / occupied.
constexpr int kSaveFreeMax = 19;
constexpr int kSaveOccupiedMin = 65;

[[noreturn]] void ThrowKeyError(const std::string& yaml_path, const std::string& key,
                                const std::string& what) {
  throw MapFileError(yaml_path + ": key '" + key + "': " + what);
}

// The node as written in the file, for error messages.
std::string NodeText(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  std::string text = YAML::Dump(node);
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

// Shortest decimal text that parses back to exactly `value`.
std::string ExactDecimal(double value) {
  if (value == 0.0) value = 0.0;  // no "-0"
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  std::string text(buffer.data(), result.ptr);
  // Keep it a YAML float rather than an int ("1" -> "1.0").
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

YAML::Node RequiredKey(const YAML::Node& root, const std::string& yaml_path,
                       const std::string& key) {
  const YAML::Node node = root[key];
  if (!node || node.IsNull()) {
    throw MapFileError(yaml_path + ": missing required key '" + key + "'");
  }
  return node;
}

double ParseNumber(const YAML::Node& node, const std::string& yaml_path, const std::string& key) {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    ThrowKeyError(yaml_path, key, "expected a number, got '" + NodeText(node) + "'");
  }
  return value;
}

double ParseThreshold(const YAML::Node& root, const std::string& yaml_path, const std::string& key,
                      double default_value) {
  const YAML::Node node = root[key];
  if (!node) return default_value;
  const double value = ParseNumber(node, yaml_path, key);
  if (value < 0.0 || value > 1.0) {
    ThrowKeyError(yaml_path, key, "expected a number in [0, 1], got '" + NodeText(node) + "'");
  }
  return value;
}

bool ParseNegate(const YAML::Node& root, const std::string& yaml_path) {
  const YAML::Node node = root["negate"];
  if (!node) return false;
  // map_server reads negate as an int; accept YAML booleans too.
  int as_int = 0;
  bool as_bool = false;
  if (node.IsScalar() && YAML::convert<int>::decode(node, as_int) && (as_int == 0 || as_int == 1)) {
    return as_int == 1;
  }
  if (node.IsScalar() && YAML::convert<bool>::decode(node, as_bool)) return as_bool;
  ThrowKeyError(yaml_path, "negate", "expected 0 or 1, got '" + NodeText(node) + "'");
}

MapMode ParseMode(const YAML::Node& root, const std::string& yaml_path) {
  const YAML::Node node = root["mode"];
  if (!node) return MapMode::kTrinary;
  const std::string text = node.IsScalar() ? node.Scalar() : NodeText(node);
  if (text == "trinary") return MapMode::kTrinary;
  if (text == "scale") return MapMode::kScale;
  if (text == "raw") return MapMode::kRaw;
  ThrowKeyError(yaml_path, "mode", "expected trinary, scale or raw, got '" + text + "'");
}

Pose2d ParseOrigin(const YAML::Node& root, const std::string& yaml_path) {
  const YAML::Node node = RequiredKey(root, yaml_path, "origin");
  if (!node.IsSequence() || node.size() != 3) {
    ThrowKeyError(yaml_path, "origin", "expected [x, y, yaw], got '" + NodeText(node) + "'");
  }
  Pose2d origin{ParseNumber(node[0], yaml_path, "origin"),
                ParseNumber(node[1], yaml_path, "origin"),
                ParseNumber(node[2], yaml_path, "origin")};
  if (origin.yaw_rad != 0.0) {
    ThrowKeyError(yaml_path, "origin",
                  "a rotated map (yaw " + NodeText(node[2]) + ") is not supported, yaw must be 0");
  }
  return origin;
}

MapMetadata ParseMetadata(const YAML::Node& root, const std::string& yaml_path) {
  if (!root.IsMap()) throw MapFileError(yaml_path + ": expected a YAML mapping of map keys");
  MapMetadata metadata;

  const YAML::Node image = RequiredKey(root, yaml_path, "image");
  if (!image.IsScalar() || image.Scalar().empty()) {
    ThrowKeyError(yaml_path, "image", "expected an image file name, got '" + NodeText(image) + "'");
  }
  metadata.image = image.Scalar();

  const YAML::Node resolution = RequiredKey(root, yaml_path, "resolution");
  metadata.resolution_m = ParseNumber(resolution, yaml_path, "resolution");
  if (!(metadata.resolution_m > 0.0)) {
    ThrowKeyError(yaml_path, "resolution",
                  "expected a positive number, got '" + NodeText(resolution) + "'");
  }

  metadata.origin = ParseOrigin(root, yaml_path);
  metadata.negate = ParseNegate(root, yaml_path);
  metadata.occupied_thresh = ParseThreshold(root, yaml_path, "occupied_thresh", 0.65);
  metadata.free_thresh = ParseThreshold(root, yaml_path, "free_thresh", 0.196);
  if (metadata.free_thresh >= metadata.occupied_thresh) {
    ThrowKeyError(yaml_path, "free_thresh",
                  "must be below occupied_thresh (" + ExactDecimal(metadata.occupied_thresh) +
                      "), got '" + ExactDecimal(metadata.free_thresh) + "'");
  }
  metadata.mode = ParseMode(root, yaml_path);
  return metadata;
}

// Cell value of every pixel value, exactly as ROS map_server's image loader
// computes it (scale mode: 1 + 98 * ratio, truncated like its int conversion).
std::array<int8_t, 256> PixelToCellTable(const MapMetadata& metadata) {
  std::array<int8_t, 256> table{};
  for (int pixel = 0; pixel < 256; ++pixel) {
    const int shade = metadata.negate ? 255 - pixel : pixel;
    if (metadata.mode == MapMode::kRaw) {
      // map_server copies the byte; anything outside 0..100 means unknown here.
      table[pixel] =
          shade <= OccupancyGrid::kOccupied ? static_cast<int8_t>(shade) : OccupancyGrid::kUnknown;
      continue;
    }
    const double occupancy = (255.0 - shade) / 255.0;
    if (occupancy > metadata.occupied_thresh) {
      table[pixel] = OccupancyGrid::kOccupied;
    } else if (occupancy < metadata.free_thresh) {
      table[pixel] = OccupancyGrid::kFree;
    } else if (metadata.mode == MapMode::kTrinary) {
      table[pixel] = OccupancyGrid::kUnknown;
    } else {
      const double ratio =
          (occupancy - metadata.free_thresh) / (metadata.occupied_thresh - metadata.free_thresh);
      table[pixel] = static_cast<int8_t>(1.0 + 98.0 * ratio);
    }
  }
  return table;
}

std::array<uint8_t, 256> CellToPixelTable() {
  std::array<uint8_t, 256> table{};
  for (int index = 0; index < 256; ++index) {
    const int value = static_cast<int8_t>(index);  // the cell byte read as signed
    if (value >= 0 && value <= kSaveFreeMax) {
      table[index] = kFreePixel;
    } else if (value >= kSaveOccupiedMin && value <= OccupancyGrid::kOccupied) {
      table[index] = kOccupiedPixel;
    } else {
      table[index] = kUnknownPixel;
    }
  }
  return table;
}

}  // namespace

LoadedMap LoadMap(const std::string& yaml_path) {
  std::error_code error;
  if (!fs::is_regular_file(yaml_path, error)) {
    throw MapFileError(yaml_path + ": map file not found");
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::ParserException& e) {
    throw MapFileError(yaml_path + ":" + std::to_string(e.mark.line + 1) +
                       ": malformed YAML: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw MapFileError(yaml_path + ": cannot read: " + e.what());
  }

  LoadedMap loaded;
  loaded.metadata = ParseMetadata(root, yaml_path);
  const fs::path image_path(loaded.metadata.image);
  loaded.image_path = image_path.is_absolute()
                          ? image_path.string()
                          : (fs::path(yaml_path).parent_path() / image_path).string();

  if (!fs::is_regular_file(loaded.image_path, error)) {
    ThrowKeyError(yaml_path, "image", "image file '" + loaded.image_path + "' not found");
  }
  cv::Mat image;
  try {
    image = cv::imread(loaded.image_path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    image.release();  // reported below like any other undecodable file
  }
  if (image.empty()) {
    ThrowKeyError(yaml_path, "image",
                  "'" + loaded.image_path + "' is not a readable PGM or PNG image");
  }

  const std::array<int8_t, 256> table = PixelToCellTable(loaded.metadata);
  cv::Mat cells_top_down;
  cv::LUT(image, cv::Mat(1, 256, CV_8S, const_cast<int8_t*>(table.data())), cells_top_down);
  // Image row 0 is the top of the map; grid row 0 is the bottom.
  cv::Mat cells_bottom_up;
  cv::flip(cells_top_down, cells_bottom_up, 0);

  loaded.grid = OccupancyGrid(image.cols, image.rows, loaded.metadata.resolution_m,
                              {loaded.metadata.origin.x_m, loaded.metadata.origin.y_m});
  std::memcpy(loaded.grid.mutable_cells().data(), cells_bottom_up.data,
              loaded.grid.mutable_cells().size());
  return loaded;
}

void WriteImageAtomically(const std::string& path, const cv::Mat& image) {
  std::vector<uint8_t> encoded;
  try {
    if (!cv::imencode(fs::path(path).extension().string(), image, encoded))
      throw MapFileError(path + ": cannot encode image");
  } catch (const cv::Exception& e) {
    throw MapFileError(path + ": cannot encode image: " + e.what());
  }
  try {
    WriteFileAtomically(
        path, std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
  } catch (const std::runtime_error& e) {
    throw MapFileError(e.what());
  }
}

void SaveMap(const OccupancyGrid& grid, const std::string& base_path, MapImageFormat format) {
  if (grid.empty()) throw MapFileError(base_path + ": cannot save an empty grid");
  const std::string image_path = base_path + (format == MapImageFormat::kPng ? ".png" : ".pgm");
  const std::string yaml_path = base_path + ".yaml";

  const cv::Mat cells_bottom_up(grid.height_cells(), grid.width_cells(), CV_8U,
                                const_cast<int8_t*>(grid.cells().data()));
  const std::array<uint8_t, 256> table = CellToPixelTable();
  cv::Mat pixels_bottom_up;
  cv::LUT(cells_bottom_up, cv::Mat(1, 256, CV_8U, const_cast<uint8_t*>(table.data())),
          pixels_bottom_up);
  cv::Mat image;
  cv::flip(pixels_bottom_up, image, 0);

  WriteImageAtomically(image_path, image);

  YAML::Emitter yaml;
  yaml << YAML::BeginMap;
  yaml << YAML::Key << "image" << YAML::Value << fs::path(image_path).filename().string();
  yaml << YAML::Key << "mode" << YAML::Value << "trinary";
  yaml << YAML::Key << "resolution" << YAML::Value << ExactDecimal(grid.resolution_m());
  yaml << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginSeq
       << ExactDecimal(grid.origin_m().x_m) << ExactDecimal(grid.origin_m().y_m) << "0.0"
       << YAML::EndSeq;
  yaml << YAML::Key << "negate" << YAML::Value << 0;
  yaml << YAML::Key << "occupied_thresh" << YAML::Value << "0.65";
  yaml << YAML::Key << "free_thresh" << YAML::Value << "0.196";
  yaml << YAML::EndMap;

  try {
    WriteFileAtomically(yaml_path, std::string(yaml.c_str()) + "\n");
  } catch (const std::runtime_error& e) {
    throw MapFileError(e.what());
  }
}

}  // namespace aslam
