#pragma once

// World folders, as aslam-worldgen writes them and the simulator and the
// evaluation read them:
//
//   DIR/world.yaml              start pose, free area (and generator parameters)
//   DIR/map.yaml, DIR/map.pgm   ground truth, ROS map_server format
//
// A bare map_server YAML is a world too, without a start.

#include <string>

#include "common/map_io.h"
#include "common/pose2d.h"

namespace aslam {

struct WorldInfo {
  std::string map_yaml_path;
  std::string world_yaml_path;  // empty for a bare map
  bool has_start = false;       // a bare map has no start
  Pose2d start;
  double free_area_m2 = 0.0;  // from world.yaml; for a bare map its free cells
  LoadedMap map;
};

// Loads a world folder (DIR/world.yaml naming its map, map.yaml by default),
// a world.yaml path, or a bare map YAML. Throws std::runtime_error naming the
// file and key (a bad map throws MapFileError), also if the start is not on a
// free cell of the map.
WorldInfo LoadWorld(const std::string& dir_or_yaml);

}  // namespace aslam
