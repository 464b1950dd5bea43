#include "navigation/nav_node.h"

#include <algorithm>

#include "aslam/velocity_command_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "navigation/nav_lcm.h"

namespace aslam {
namespace {

constexpr int64_t kStatusHeartbeatUs = 1'000'000;

}  // namespace

NavNode::NavNode(lcm::LCM& lcm, NavOptions options)
    : lcm_(lcm), navigator_(std::move(options)), subscriptions_(lcm) {
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& m) { return OnPose(m); });
  AddMapSubscription(subscriptions_, channels::kSlamMap,
                     [this](MapMessage m) { return OnMap(std::move(m)); });
  AddLidarScanSubscription(subscriptions_, channels::kLidarScan,
                           [this](const LidarScan& scan) { return OnScan(scan); });
  subscriptions_.Add<explore_goal_t>(channels::kExploreGoal,
                                     [this](const explore_goal_t& m) { return OnGoal(m); });
}

void NavNode::NoteTime(int64_t utime) {
  if (!scan_clock_.started()) latest_utime_ = std::max(latest_utime_, utime);
}

bool NavNode::OnPose(const pose_t& msg) {
  const auto pose = MapFramePoseFromLcm(msg);
  if (!pose) return false;
  NoteTime(pose->utime);
  navigator_.SetPose(*pose);
  // Without scans there are no control cycles; keep NAV_STATUS alive anyway.
  if (pose->utime - last_status_utime_ >= kStatusHeartbeatUs) {
    NavStatus status = navigator_.status();
    status.utime = pose->utime;
    PublishStatus(status);
  }
  return true;
}

bool NavNode::OnMap(MapMessage msg) {
  NoteTime(msg.utime);
  navigator_.SetMap(msg.grid);
  PublishObstaclesIfChanged();
  return true;
}

bool NavNode::OnScan(const LidarScan& scan) {
  const StreamClock::Verdict verdict = scan_clock_.Offer(scan.utime);
  if (!StreamClock::Accepted(verdict)) return false;
  if (verdict == StreamClock::Verdict::kResynced) navigator_.RestartClock(scan.utime);
  latest_utime_ = scan.utime;
  navigator_.SetScan(scan);
  const NavOutput out = navigator_.Step(scan.utime);
  const velocity_command_t command = ToLcm(out.command);
  lcm_.publish(channels::kCmdVel, &command);
  ++commands_published_;
  PublishObstaclesIfChanged();
  PublishStatus(out.status);
  PublishPathIfChanged(scan.utime);
  return true;
}

bool NavNode::OnGoal(const explore_goal_t& msg) {
  const auto request = FromLcm(msg);
  if (!request) return false;
  NoteTime(request->utime);
  if (request->cancel) {
    navigator_.Cancel(request->goal_id, request->utime);
  } else {
    navigator_.SetGoal(request->goal_id, request->goal_m, request->utime);
  }
  PublishStatus(navigator_.status());
  PublishPathIfChanged(request->utime);
  return true;
}

void NavNode::PublishStatus(const NavStatus& status) {
  const nav_status_t msg = ToLcm(status);
  lcm_.publish(channels::kNavStatus, &msg);
  last_status_utime_ = status.utime;
}

void NavNode::PublishPathIfChanged(int64_t utime) {
  if (navigator_.path_revision() == published_path_revision_) return;
  published_path_revision_ = navigator_.path_revision();
  const nav_path_t msg = PathToLcm(utime, navigator_.status().goal_id, navigator_.path_m(),
                                   navigator_.path_length_m());
  lcm_.publish(channels::kNavPath, &msg);
}

void NavNode::PublishObstaclesIfChanged() {
  if (navigator_.marks_revision() == published_marks_revision_) return;
  published_marks_revision_ = navigator_.marks_revision();
  const nav_obstacles_t msg = ToLcm(navigator_.planning_obstacles());
  lcm_.publish(channels::kNavObstacles, &msg);
}

void NavNode::PublishStop() {
  const velocity_command_t command = ToLcm(VelocityCommand{latest_utime_, 0.0, 0.0});
  lcm_.publish(channels::kCmdVel, &command);
  ++commands_published_;
}

}  // namespace aslam
