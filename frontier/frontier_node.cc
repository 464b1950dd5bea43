#include "frontier/frontier_node.h"

#include <utility>

#include "aslam/frontier_list_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"

namespace aslam {

FrontierNode::FrontierNode(lcm::LCM& lcm, FrontierOptions options)
    : lcm_(lcm), extractor_(std::move(options)), subscriptions_(lcm) {
  AddMapSubscription(subscriptions_, channels::kSlamMap,
                     [this](MapMessage m) { return OnMap(std::move(m)); });
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) { return OnPose(m); });
}

bool FrontierNode::OnMap(MapMessage msg) {
  // "New" = different: a restarted SLAM counts its revisions from the start again.
  if (published_ && published_->map_revision == msg.revision) {
    // SLAM's re-announcement of an unchanged map: re-announce the list that answers it, so a
    // restarted utility gets FRONTIERS while the robot stands still (no new revision comes).
    published_->utime = msg.utime;
    Publish();
    return true;
  }
  map_ = std::move(msg.grid);
  map_utime_ = msg.utime;
  map_revision_ = msg.revision;
  map_pending_ = true;
  if (pose_) ExtractAndPublish();
  return true;
}

bool FrontierNode::OnPose(const pose_t& msg) {
  const std::optional<StampedPose> pose = MapFramePoseFromLcm(msg);
  if (!pose) return false;
  pose_ = pose;
  if (map_pending_) ExtractAndPublish();
  return true;
}

void FrontierNode::ExtractAndPublish() {
  map_pending_ = false;
  published_ = FrontierList{};
  published_->utime = map_utime_;
  published_->map_revision = map_revision_;
  published_->frontiers = extractor_.Extract(*map_, {pose_->pose.x_m, pose_->pose.y_m});
  Publish();
}

void FrontierNode::Publish() {
  const frontier_list_t msg = ToLcm(*published_);
  lcm_.publish(channels::kFrontiers, &msg);
  ++lists_published_;
}

}  // namespace aslam
