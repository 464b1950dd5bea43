#include "slam/slam_lcm.h"

#include <algorithm>
#include <limits>

#include "common/channels.h"
#include "common/types_lcm.h"

namespace aslam {
namespace {

// The message's counters are int32: saturate rather than wrap.
int32_t Saturated(int64_t count) {
  return static_cast<int32_t>(std::min<int64_t>(count, std::numeric_limits<int32_t>::max()));
}

}  // namespace

pose_t SlamPoseToLcm(const StampedPose& pose, const Eigen::Matrix3d& covariance) {
  pose_t msg = ToLcm(pose, kMapFrame);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) msg.covariance[3 * r + c] = covariance(r, c);
  }
  return msg;
}

pose_graph_t SlamGraphToLcm(const Slam& slam, int64_t utime) {
  const SlamCounters& counters = slam.counters();
  return ToLcm(slam.graph(), utime, slam.graph_revision(),
               Saturated(counters.loop_closures_accepted),
               Saturated(counters.loop_closures_rejected));
}

void PublishSlamMap(lcm::LCM& lcm, const OccupancyGrid& map, int64_t utime, int64_t revision,
                    SlamNodeOptions::MapEncoding encoding) {
  if (encoding == SlamNodeOptions::MapEncoding::kRaw) {
    const occupancy_grid_t msg = ToLcm(map, utime, revision, kMapFrame);
    lcm.publish(channels::kSlamMap, &msg);
  } else {
    const compressed_occupancy_grid_t msg = ToCompressedLcm(map, utime, revision, kMapFrame);
    lcm.publish(channels::kSlamMap, &msg);
  }
}

}  // namespace aslam
