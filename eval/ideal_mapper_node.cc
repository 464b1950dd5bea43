#include "eval/ideal_mapper_node.h"

#include <cmath>

#include "aslam/odometry_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "slam/slam_lcm.h"

namespace aslam {

IdealMapperNode::IdealMapperNode(lcm::LCM& lcm, const SlamOptions& slam_options,
                                 SlamNodeOptions node_options)
    : lcm_(lcm),
      mapper_(slam_options.mapper, slam_options.keyframe),
      node_options_(node_options),
      subscriptions_(lcm) {
  subscriptions_.Add<pose_t>(channels::kSimTruth, [this](const pose_t& m) {
    const auto truth = FromLcm(m);
    if (!truth) return false;
    mapper_.AddTruth({truth->utime, truth->pose});
    MapPendingScans(/*flush=*/false);
    return true;
  });
  subscriptions_.Add<odometry_t>(channels::kOdometry, [this](const odometry_t& m) {
    const auto odometry = FromLcm(m);
    if (!odometry) return false;
    linear_velocity_mps_ = odometry->linear_velocity_mps;
    angular_velocity_radps_ = odometry->angular_velocity_radps;
    return true;
  });
  AddLidarScanSubscription(subscriptions_, channels::kLidarScan, [this](const LidarScan& scan) {
    pending_scans_.push_back(scan);
    // More than one waiting: truth has stopped coming, so map with what there is.
    MapPendingScans(/*flush=*/pending_scans_.size() > 2);
    return true;
  });
}

void IdealMapperNode::MapPendingScans(bool flush) {
  const std::optional<int64_t> truth_utime = mapper_.newest_truth_utime();
  while (!pending_scans_.empty()) {
    const LidarScan& scan = pending_scans_.front();
    const double sweep_s = scan.beam_time_s.empty() ? 0.0 : scan.beam_time_s.back();
    const bool covered = truth_utime && *truth_utime >= scan.utime + std::llround(sweep_s * 1e6);
    if (!covered && !flush) return;
    MapScan(scan);
    pending_scans_.pop_front();
  }
}

void IdealMapperNode::MapScan(const LidarScan& scan) {
  const std::optional<Pose2d> pose = mapper_.AddScan(scan);
  if (!pose) return;
  const pose_t pose_msg = ToLcm(
      StampedPose{scan.utime, *pose, linear_velocity_mps_, angular_velocity_radps_}, kMapFrame);
  lcm_.publish(channels::kSlamPose, &pose_msg);

  const bool due = !map_published_ || scan.utime < last_map_utime_ ||
                   scan.utime - last_map_utime_ >= std::llround(node_options_.map_period_s * 1e6);
  if (!due) return;
  if (mapper_.graph().nodes.size() != published_keyframes_) {
    const pose_graph_t graph_msg = ToLcm(mapper_.graph(), scan.utime,
                                         static_cast<int64_t>(mapper_.graph().nodes.size()), 0, 0);
    lcm_.publish(channels::kPoseGraph, &graph_msg);
    published_keyframes_ = mapper_.graph().nodes.size();
  }
  if (mapper_.map_revision() != published_map_revision_) {
    PublishSlamMap(lcm_, mapper_.RenderMap(), scan.utime, mapper_.map_revision(),
                   node_options_.map_encoding);
    published_map_revision_ = mapper_.map_revision();
  }
  last_map_utime_ = scan.utime;
  map_published_ = true;
}

}  // namespace aslam
