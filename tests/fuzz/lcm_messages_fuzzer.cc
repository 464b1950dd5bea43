// libFuzzer: every LCM message a node accepts, decoded from arbitrary bytes and, when it
// decodes, through the translator that validates it (README: scripts/fuzz).

#include <cstddef>
#include <cstdint>

#include "aslam/compressed_occupancy_grid_t.hpp"
#include "aslam/explore_goal_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/lidar_scan_t.hpp"
#include "aslam/nav_obstacles_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/occupancy_grid_t.hpp"
#include "aslam/odometry_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_lcm.h"

namespace {

// Decodes `Msg` from the bytes and, if that works, validates it with `translate`.
template <typename Msg, typename Translate>
void DecodeAndTranslate(const uint8_t* data, std::size_t size, Translate translate) {
  Msg msg;
  if (msg.decode(data, 0, static_cast<int>(size)) < 0) return;
  translate(msg);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace aslam;
  if (size < 1) return 0;
  const uint8_t which = data[0] % 10;
  ++data;
  --size;
  switch (which) {
    case 0:
      (void)DecodeLidarScan(data, static_cast<int>(size));  // both wire types of LIDAR_SCAN
      break;
    case 1:
      DecodeAndTranslate<odometry_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
    case 2:
      DecodeAndTranslate<pose_t>(data, size, [](const auto& m) {
        (void)FromLcm(m);
        (void)MapFramePoseFromLcm(m);
      });
      break;
    case 3:
      DecodeAndTranslate<occupancy_grid_t>(data, size, [](const auto& m) {
        (void)FromLcm(m);
        (void)MapFrameGridFromLcm(m);
      });
      break;
    case 4:
      DecodeAndTranslate<pose_graph_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
    case 5:
      DecodeAndTranslate<frontier_list_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
    case 6:
      DecodeAndTranslate<nav_status_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
    case 7:
      DecodeAndTranslate<explore_goal_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
    case 8:
      DecodeAndTranslate<compressed_occupancy_grid_t>(data, size, [](const auto& m) {
        (void)FromLcm(m);
        (void)MapFrameGridFromLcm(m);
      });
      break;
    case 9:
      DecodeAndTranslate<nav_obstacles_t>(data, size, [](const auto& m) { (void)FromLcm(m); });
      break;
  }
  return 0;
}
