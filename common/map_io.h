#pragma once

// ROS map_server map files: a YAML file naming an image (PGM or PNG) with
// resolution, origin, negate, occupied_thresh, free_thresh and mode.

#include <stdexcept>
#include <string>

#include <opencv2/core/mat.hpp>

#include "common/occupancy_grid.h"

namespace aslam {

// Bad map files: the message names the file, the key or value at fault.
class MapFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How image pixels become cell values (map_server's `mode`).
enum class MapMode { kTrinary, kScale, kRaw };

struct MapMetadata {
  std::string image;  // as written in the YAML (relative to the YAML's folder)
  double resolution_m = 0.05;
  Pose2d origin;  // lower-left pixel's corner in the map frame
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapMode mode = MapMode::kTrinary;
};

struct LoadedMap {
  OccupancyGrid grid;  // origin taken from the YAML (yaw must be 0)
  MapMetadata metadata;
  std::string image_path;  // resolved path of the image file
};

// Loads a map_server YAML and its image. Required keys: image (relative to
// the YAML's folder unless absolute), resolution, origin; negate,
// occupied_thresh, free_thresh and mode default to 0, 0.65, 0.196, trinary.
// Pixels become cells as in ROS map_server: p = (255 - v) / 255 (v / 255 if
// negate); p > occupied_thresh -> 100, p < free_thresh -> 0, otherwise -1
// (trinary) or 1 + 98 * (p - free) / (occupied - free) truncated (scale);
// raw copies v, with bytes above 100 read as unknown. Image row 0 is the top
// of the map, grid row 0 the bottom. Throws MapFileError on a missing or
// malformed YAML, a missing key, an out-of-range value (resolution <= 0,
// thresholds outside [0, 1] or free_thresh >= occupied_thresh, non-zero
// origin yaw), a missing image or data that is not a decodable image.
LoadedMap LoadMap(const std::string& yaml_path);

enum class MapImageFormat { kPgm, kPng };

// Writes `<base_path>.yaml` and `<base_path>.pgm|.png` the way map_saver
// does (trinary: free 254, occupied 0, unknown 205; occupied_thresh 0.65,
// free_thresh 0.196). Cells in 1..100 at or above 65 are written occupied,
// at or below 19 free, others unknown. Each file is written atomically
// (common/atomic_file.h). Throws MapFileError if a file cannot be written.
void SaveMap(const OccupancyGrid& grid, const std::string& base_path,
             MapImageFormat format = MapImageFormat::kPgm);

// Encodes `image` by `path`'s extension (.pgm, .png, ...) and writes it atomically
// (common/atomic_file.h); throws MapFileError naming the path.
void WriteImageAtomically(const std::string& path, const cv::Mat& image);

}  // namespace aslam
