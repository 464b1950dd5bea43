#include "viewer/viewer_lcm.h"

#include <utility>

#include "aslam/explore_control_t.hpp"
#include "aslam/explore_status_t.hpp"
#include "aslam/frontier_list_t.hpp"
#include "aslam/nav_path_t.hpp"
#include "aslam/nav_status_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "aslam/procman_status_t.hpp"
#include "aslam/utility_scores_t.hpp"
#include "common/channels.h"
#include "common/types_lcm.h"
#include "frontier/frontier_lcm.h"
#include "navigation/nav_lcm.h"
#include "procman/procman_lcm.h"
#include "utility/utility_lcm.h"

namespace aslam {

const std::vector<std::string>& ViewerChannels() {
  static const std::vector<std::string> channels = {
      channels::kSlamMap,      channels::kSlamPose,  channels::kLidarScan,
      channels::kPoseGraph,    channels::kFrontiers, channels::kUtilityScores,
      channels::kNavStatus,    channels::kNavPath,   channels::kExploreStatus,
      channels::kProcmanStatus};
  return channels;
}

ViewerNode::ViewerNode(lcm::LCM& lcm) : lcm_(lcm), subscriptions_(lcm) {
  AddMapSubscription(subscriptions_, channels::kSlamMap, [this](MapMessage m) {
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnMap(m.grid, m.revision, m.utime);
    return true;
  });
  subscriptions_.Add<pose_t>(channels::kSlamPose, [this](const pose_t& msg) {
    const auto pose = MapFramePoseFromLcm(msg);
    if (!pose) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnPose(*pose);
    return true;
  });
  AddLidarScanSubscription(subscriptions_, channels::kLidarScan, [this](const LidarScan& scan) {
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnScan(scan);
    return true;
  });
  subscriptions_.Add<pose_graph_t>(channels::kPoseGraph, [this](const pose_graph_t& msg) {
    const auto graph = FromLcm(msg);
    if (!graph) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnGraph(*graph, msg.utime);
    return true;
  });
  subscriptions_.Add<frontier_list_t>(channels::kFrontiers, [this](const frontier_list_t& msg) {
    const auto list = FromLcm(msg);
    if (!list) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnFrontiers(*list);
    return true;
  });
  subscriptions_.Add<utility_scores_t>(
      channels::kUtilityScores, [this](const utility_scores_t& msg) {
        std::optional<std::vector<FrontierScore>> scores = FrontierScoresFromLcm(msg);
        if (!scores) return false;
        std::lock_guard<std::mutex> lock(mutex_);
        model_.OnScores({msg.decision_id, msg.method, msg.chosen_frontier_id, std::move(*scores)},
                        msg.utime);
        return true;
      });
  subscriptions_.Add<nav_status_t>(channels::kNavStatus, [this](const nav_status_t& msg) {
    const auto status = FromLcm(msg);
    if (!status) return false;
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnNavStatus(*status);
    return true;
  });
  subscriptions_.Add<nav_path_t>(channels::kNavPath, [this](const nav_path_t& msg) {
    if (msg.num_points != static_cast<int>(msg.x_m.size()) || msg.x_m.size() != msg.y_m.size()) {
      return false;
    }
    std::vector<Point2d> path;
    path.reserve(msg.x_m.size());
    for (std::size_t i = 0; i < msg.x_m.size(); ++i) path.push_back({msg.x_m[i], msg.y_m[i]});
    std::lock_guard<std::mutex> lock(mutex_);
    model_.OnNavPath(std::move(path), msg.utime);
    return true;
  });
  subscriptions_.Add<explore_status_t>(channels::kExploreStatus,
                                       [this](const explore_status_t& msg) {
                                         const std::optional<ExploreStatus> status = FromLcm(msg);
                                         if (!status) return false;
                                         std::lock_guard<std::mutex> lock(mutex_);
                                         model_.OnExploreStatus(*status);
                                         return true;
                                       });
  subscriptions_.Add<procman_status_t>(channels::kProcmanStatus,
                                       [this](const procman_status_t& msg) {
                                         DeputyStatus status;
                                         if (!FromLcm(msg, &status)) return false;
                                         std::lock_guard<std::mutex> lock(mutex_);
                                         model_.OnProcesses(status);
                                         return true;
                                       });
}

std::string ViewerNode::Update(ViewerCursor* cursor) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return model_.Update(cursor);
}

double ViewerNode::t_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return model_.t_s();
}

void ViewerNode::SetModel(ViewerModel model) {
  std::lock_guard<std::mutex> lock(mutex_);
  model_ = std::move(model);
}

ViewerModel ViewerNode::model() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return model_;
}

void ViewerNode::SendControl(ExploreCommand command, const std::string& source) {
  const explore_control_t msg = ExploreControlMessage(command, source);
  lcm_.publish(channels::kExploreControl, &msg);
}

}  // namespace aslam
