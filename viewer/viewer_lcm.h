#pragma once

// The viewer on LCM: subscribes every channel it shows (SLAM_MAP, SLAM_POSE, LIDAR_SCAN,
// POSE_GRAPH, FRONTIERS, UTILITY_SCORES, NAV_STATUS, NAV_PATH, EXPLORE_STATUS,
// PROCMAN_STATUS), translates each message into the ViewerModel's value types, and publishes
// the pages' EXPLORE_CONTROL requests. Handlers run in the thread that calls lcm.handle();
// the server's threads read the model through Update(), so the model sits behind a mutex.

#include <mutex>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/lcm_util.h"
#include "utility/exploration_manager.h"
#include "viewer/viewer_model.h"

namespace aslam {

// Every channel the viewer reads.
const std::vector<std::string>& ViewerChannels();

class ViewerNode {
 public:
  explicit ViewerNode(lcm::LCM& lcm);

  // ViewerModel::Update under the lock.
  std::string Update(ViewerCursor* cursor) const;
  double t_s() const;
  // Replaces the model (a replay's seek), under the lock.
  void SetModel(ViewerModel model);
  ViewerModel model() const;
  // Publishes EXPLORE_CONTROL; safe from any thread (LCM's publish is).
  void SendControl(ExploreCommand command, const std::string& source);

  const Subscriptions& subscriptions() const { return subscriptions_; }

 private:
  lcm::LCM& lcm_;
  mutable std::mutex mutex_;
  ViewerModel model_;
  Subscriptions subscriptions_;
};

}  // namespace aslam
