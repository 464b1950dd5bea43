#pragma once

// The ideal explorer's mapping (`--method ideal`, an evaluation baseline): every scan inserted
// at the simulator's true pose, each beam placed by the true motion at its own time, so the map
// is as good as the lidar allows and no localization error exists. It reads truth, so it lives
// in eval/ (docs/architecture.md §3). Its "map" frame is the true pose of the first scan, as
// SLAM's is the first keyframe's; its pose graph is keyframes at true poses, without edges.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "eval/trajectory_metrics.h"
#include "slam/occupancy_mapper.h"
#include "slam/slam_options.h"

namespace aslam {

class IdealMapper {
 public:
  // Throws std::invalid_argument for invalid mapper options (naming the option).
  IdealMapper(OccupancyMapperOptions mapper, KeyframeOptions keyframe);

  // A true pose ("world"); samples older than the newest are ignored.
  void AddTruth(const TimedPose& truth);
  // Inserts the scan at the true pose of its time and returns the base's pose in "map" then;
  // nullopt (nothing inserted) while no truth lies within 0.1 s of the scan's time.
  std::optional<Pose2d> AddScan(const LidarScan& scan);

  // The newest true pose's time; a scan is best added once this covers its last beam.
  std::optional<int64_t> newest_truth_utime() const;

  OccupancyGrid RenderMap() const { return mapper_.Render(); }
  // Keyframes at true poses ("map"), one per KeyframeOptions of travel or rotation.
  const PoseGraph& graph() const { return graph_; }
  int64_t map_revision() const { return map_revision_; }

 private:
  // The true pose at `utime`, interpolated; held at the ends within the gap.
  std::optional<Pose2d> TruthAt(int64_t utime) const;

  OccupancyMapper mapper_;
  KeyframeOptions keyframe_;
  std::vector<TimedPose> truth_;          // the last few seconds, in time order
  std::optional<Pose2d> world_from_map_;  // the first scan's true pose
  PoseGraph graph_;
  int64_t map_revision_ = 0;
};

}  // namespace aslam
