#include "eval/ideal_mapper.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "slam/scan_deskew.h"

namespace aslam {
namespace {

constexpr int64_t kTruthGapUs = 100'000;
constexpr int64_t kTruthKeptUs = 3'000'000;  // longer than any sweep

}  // namespace

IdealMapper::IdealMapper(OccupancyMapperOptions mapper, KeyframeOptions keyframe)
    : mapper_(mapper), keyframe_(keyframe) {}

void IdealMapper::AddTruth(const TimedPose& truth) {
  if (!truth_.empty() && truth.utime <= truth_.back().utime) return;
  truth_.push_back(truth);
  // Trimmed in batches: erasing the front of a vector per sample would cost a copy each.
  if (truth_.front().utime < truth.utime - 2 * kTruthKeptUs) {
    const auto keep = std::lower_bound(
        truth_.begin(), truth_.end(), truth.utime - kTruthKeptUs,
        [](const TimedPose& sample, int64_t utime) { return sample.utime < utime; });
    truth_.erase(truth_.begin(), keep);
  }
}

std::optional<int64_t> IdealMapper::newest_truth_utime() const {
  if (truth_.empty()) return std::nullopt;
  return truth_.back().utime;
}

std::optional<Pose2d> IdealMapper::TruthAt(int64_t utime) const {
  return PoseAt(truth_, utime, kTruthGapUs);
}

std::optional<Pose2d> IdealMapper::AddScan(const LidarScan& scan) {
  const std::optional<Pose2d> base_in_world = TruthAt(scan.utime);
  if (!base_in_world) return std::nullopt;
  if (!world_from_map_) world_from_map_ = *base_in_world;
  const Pose2d base_in_map = world_from_map_->Between(*base_in_world);
  // Each beam where the base truly was at its time, seen from the pose at the scan's time.
  const LidarScan placed = DeskewScan(scan, [&](double seconds_after_utime) {
    const auto at = TruthAt(scan.utime + std::llround(seconds_after_utime * 1e6));
    return base_in_world->Between(at.value_or(*base_in_world));
  });
  if (mapper_.InsertScan(base_in_map, placed)) ++map_revision_;

  const bool keyframe_due = graph_.nodes.empty() || [&] {
    const Pose2d step = graph_.nodes.back().pose.Between(base_in_map);
    return std::hypot(step.x_m, step.y_m) >= keyframe_.travel_m ||
           std::abs(step.yaw_rad) >= keyframe_.rotation_rad;
  }();
  if (keyframe_due) {
    graph_.nodes.push_back({static_cast<int>(graph_.nodes.size()), scan.utime, base_in_map});
  }
  return base_in_map;
}

}  // namespace aslam
