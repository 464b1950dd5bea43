#include "common/world_file.h"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace aslam {
namespace {

namespace fs = std::filesystem;

std::string FormatNumber(double value) {
  std::ostringstream text;
  text.precision(10);
  text << value;
  return text.str();
}

[[noreturn]] void ThrowWorldError(const std::string& path, const std::string& key,
                                  const std::string& what) {
  throw std::runtime_error(path + ": key '" + key + "': " + what);
}

double ReadWorldNumber(const YAML::Node& parent, const std::string& path,
                       const std::string& key_path, const std::string& key) {
  const YAML::Node node = parent[key];
  if (!node) throw std::runtime_error(path + ": missing key '" + key_path + "'");
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    ThrowWorldError(path, key_path, "expected a number, got '" + YAML::Dump(node) + "'");
  }
  return value;
}

}  // namespace

WorldInfo LoadWorld(const std::string& dir_or_yaml) {
  const fs::path path(dir_or_yaml);
  std::error_code error;
  WorldInfo info;
  fs::path world_path;
  if (fs::is_directory(path, error)) {
    world_path = path / "world.yaml";
    if (!fs::is_regular_file(world_path, error)) {
      throw std::runtime_error(dir_or_yaml + ": not a world folder (no world.yaml)");
    }
  } else if (!fs::is_regular_file(path, error)) {
    throw std::runtime_error(dir_or_yaml + ": no such world folder or YAML file");
  } else if (path.filename() == "world.yaml") {
    world_path = path;
  } else {
    // A bare map: no start; its free area is what the map shows.
    info.map_yaml_path = dir_or_yaml;
    info.map = LoadMap(dir_or_yaml);
    info.free_area_m2 = info.map.grid.CountCells().free * info.map.grid.resolution_m() *
                        info.map.grid.resolution_m();
    return info;
  }

  info.world_yaml_path = world_path.string();
  const std::string& file = info.world_yaml_path;
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::ParserException& e) {
    throw std::runtime_error(file + ":" + std::to_string(e.mark.line + 1) +
                             ": malformed YAML: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file + ": cannot read: " + e.what());
  }
  if (!root.IsMap()) throw std::runtime_error(file + ": expected a YAML mapping");

  std::string map_name = "map.yaml";
  if (const YAML::Node map = root["map"]) {
    if (!map.IsScalar() || map.Scalar().empty()) {
      ThrowWorldError(file, "map", "expected a map YAML file name");
    }
    map_name = map.Scalar();
  }
  const fs::path map_path(map_name);
  info.map_yaml_path =
      map_path.is_absolute() ? map_path.string() : (world_path.parent_path() / map_path).string();

  const YAML::Node start = root["start"];
  if (!start) throw std::runtime_error(file + ": missing key 'start'");
  if (!start.IsMap()) ThrowWorldError(file, "start", "expected {x_m, y_m, yaw_rad}");
  info.start = {ReadWorldNumber(start, file, "start.x_m", "x_m"),
                ReadWorldNumber(start, file, "start.y_m", "y_m"),
                ReadWorldNumber(start, file, "start.yaw_rad", "yaw_rad")};
  info.has_start = true;
  info.free_area_m2 = ReadWorldNumber(root, file, "free_area_m2", "free_area_m2");
  if (!(info.free_area_m2 > 0.0)) {
    ThrowWorldError(file, "free_area_m2",
                    "expected a positive number, got '" + FormatNumber(info.free_area_m2) + "'");
  }

  info.map = LoadMap(info.map_yaml_path);
  const OccupancyGrid& grid = info.map.grid;
  const CellIndex start_cell = grid.WorldToCell({info.start.x_m, info.start.y_m});
  if (grid.ValueOr(start_cell, OccupancyGrid::kUnknown) != OccupancyGrid::kFree) {
    ThrowWorldError(file, "start",
                    "(" + FormatNumber(info.start.x_m) + ", " + FormatNumber(info.start.y_m) +
                        ") is not a free cell of " + info.map_yaml_path);
  }
  return info;
}

}  // namespace aslam
