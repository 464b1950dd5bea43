#pragma once

// The frontier extractor on LCM: subscribes SLAM_MAP and SLAM_POSE (frame
// "map"); for each new map revision, once a pose is known, extracts the
// frontiers seen from the latest pose and publishes FRONTIERS (utime = the
// map's utime). A map that arrives before any pose is extracted when the
// first pose comes. SLAM's periodic re-announcement of an unchanged map is
// answered with the same list again, restamped, not a new extraction. The
// same node runs in the aslam-frontier process and in-process on memq://
// (docs/architecture.md §4).

#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <optional>

#include "aslam/pose_t.hpp"
#include "common/lcm_util.h"
#include "common/occupancy_grid.h"
#include "common/sensor_types.h"
#include "common/types_lcm.h"
#include "frontier/frontier.h"
#include "frontier/frontier_extractor.h"

namespace aslam {

class FrontierNode {
 public:
  // Throws std::invalid_argument for invalid options.
  FrontierNode(lcm::LCM& lcm, FrontierOptions options);

  const FrontierExtractor& extractor() const { return extractor_; }
  const Subscriptions& subscriptions() const { return subscriptions_; }
  int64_t lists_published() const { return lists_published_; }

 private:
  bool OnMap(MapMessage msg);
  bool OnPose(const pose_t& msg);
  void ExtractAndPublish();
  void Publish();  // published_ on FRONTIERS

  lcm::LCM& lcm_;
  FrontierExtractor extractor_;
  Subscriptions subscriptions_;
  std::optional<StampedPose> pose_;
  // The newest map and whether it still awaits extraction (no pose yet).
  std::optional<OccupancyGrid> map_;
  int64_t map_utime_ = 0;
  int64_t map_revision_ = 0;
  bool map_pending_ = false;
  std::optional<FrontierList> published_;  // the latest list, for re-announcing
  int64_t lists_published_ = 0;
};

}  // namespace aslam
