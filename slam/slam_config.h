#pragma once

// The loader of the `slam:` config section: SlamOptions for the library and
// SlamNodeOptions for its LCM node (`slam.node`), read and validated once at
// load time (docs/architecture.md §7).

#include <string>

#include "common/config.h"
#include "slam/slam_options.h"

namespace aslam {

// How the node publishes; no algorithm here.
struct SlamNodeOptions {
  // SLAM_MAP at most once per this many seconds of message time (plus after
  // every loop closure / re-render).
  double map_period_s = 1.0;
  // SLAM_MAP and POSE_GRAPH again after this many seconds of message time without a change,
  // so a node that restarted (or a viewer that joined) gets them without waiting for one.
  double republish_period_s = 5.0;
  // SLAM_MAP's wire type. kZlib (compressed_occupancy_grid_t): a whole map in one or a few
  // datagrams, so it survives a lossy link. kRaw (occupancy_grid_t): for a bus that loses
  // nothing and where the compression's cost would show, the in-process runner's memq.
  enum class MapEncoding { kZlib, kRaw };
  MapEncoding map_encoding = MapEncoding::kZlib;
};

struct SlamConfig {
  SlamOptions slam;
  SlamNodeOptions node;
};

// Reads and validates the whole `slam` section; throws ConfigError naming file, key and value.
SlamConfig LoadSlamConfig(const ConfigReader& slam_section);
// The `slam` section of `file`; "" gives the defaults.
SlamConfig LoadSlamConfigFromFile(const std::string& file);

// The library's part of the same (the `node` subsection is checked, then left out).
SlamOptions LoadSlamOptions(const ConfigReader& slam_section);
SlamOptions LoadSlamOptionsFromFile(const std::string& file);

}  // namespace aslam
