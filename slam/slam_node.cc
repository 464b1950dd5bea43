#include "slam/slam_node.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "aslam/occupancy_grid_t.hpp"
#include "aslam/pose_graph_t.hpp"
#include "aslam/pose_t.hpp"
#include "common/channels.h"
#include "common/map_io.h"
#include "common/types_lcm.h"
#include "slam/g2o_io.h"
#include "slam/slam_lcm.h"

namespace aslam {

SlamNode::SlamNode(lcm::LCM& lcm, SlamOptions options, SlamNodeOptions node_options)
    : lcm_(lcm), slam_(std::move(options)), node_options_(node_options), subscriptions_(lcm) {
  subscriptions_.Add<odometry_t>(channels::kOdometry,
                                 [this](const odometry_t& m) { return OnOdometry(m); });
  AddLidarScanSubscription(subscriptions_, channels::kLidarScan,
                           [this](const LidarScan& scan) { return OnScan(scan); });
}

bool SlamNode::OnOdometry(const odometry_t& msg) {
  const auto odometry = FromLcm(msg);
  if (!odometry || !slam_.AddOdometry(*odometry)) return false;
  linear_velocity_mps_ = odometry->linear_velocity_mps;
  angular_velocity_radps_ = odometry->angular_velocity_radps;
  return true;
}

bool SlamNode::OnScan(const LidarScan& scan) {
  const ScanUpdate update = slam_.AddScan(scan);
  if (!update.accepted) return false;

  StampedPose pose = update.pose;
  pose.linear_velocity_mps = linear_velocity_mps_;
  pose.angular_velocity_radps = angular_velocity_radps_;
  const pose_t pose_msg = SlamPoseToLcm(pose, slam_.latest_covariance());
  lcm_.publish(channels::kSlamPose, &pose_msg);
  ++poses_published_;

  // A period passed since `since`; a clock that stepped back counts as one passing.
  auto elapsed = [&](int64_t since, double period_s) {
    return scan.utime < since || scan.utime - since >= std::llround(period_s * 1e6);
  };
  if (update.graph_changed || elapsed(last_graph_utime_, node_options_.republish_period_s)) {
    PublishGraph(scan.utime);
  }

  const bool map_changed = slam_.map_revision() != published_map_revision_;
  // Consumers must see a closure's corrected map at once, not up to a period later.
  const bool urgent = update.map_invalidated;
  const bool due = maps_published_ == 0 || elapsed(last_map_utime_, node_options_.map_period_s);
  if ((map_changed && (urgent || due)) ||
      elapsed(last_map_utime_, node_options_.republish_period_s)) {
    PublishMap(scan.utime);
  }
  if (journal_) {
    journal_->Commit(scan.utime);
    std::string why_not;
    if (journal_->WantsRewrite() && !journal_->Rewrite(slam_.Snapshot(), &why_not)) {
      std::fprintf(stderr, "aslam-slam: journal not compacted (%s); appending goes on\n",
                   why_not.c_str());
    }
  }
  return true;
}

void SlamNode::Resume(SlamSnapshot snapshot) {
  slam_.Restore(std::move(snapshot));
  if (slam_.graph().nodes.empty()) return;
  const PoseGraphNode& last = slam_.graph().nodes.back();
  const pose_t pose_msg =
      SlamPoseToLcm(StampedPose{last.utime, last.pose, 0.0, 0.0}, slam_.latest_covariance());
  lcm_.publish(channels::kSlamPose, &pose_msg);
  ++poses_published_;
  PublishGraph(last.utime);
  PublishMap(last.utime);
}

void SlamNode::set_journal(SlamJournalWriter* journal) {
  journal_ = journal;
  slam_.set_journal(journal);
}

void SlamNode::PublishGraph(int64_t utime) {
  const pose_graph_t graph_msg = SlamGraphToLcm(slam_, utime);
  lcm_.publish(channels::kPoseGraph, &graph_msg);
  last_graph_utime_ = utime;
  ++graphs_published_;
}

void SlamNode::PublishMap(int64_t utime) {
  const OccupancyGrid map = slam_.RenderMap();
  if (map.empty()) return;
  PublishSlamMap(lcm_, map, utime, slam_.map_revision(), node_options_.map_encoding);
  published_map_revision_ = slam_.map_revision();
  last_map_utime_ = utime;
  ++maps_published_;
}

bool SlamNode::WriteOutputs(const std::string& dir) {
  std::filesystem::create_directories(dir);
  WriteG2o(slam_.graph(), dir + "/graph.g2o");
  const OccupancyGrid map = slam_.RenderMap();
  if (map.empty()) return false;
  SaveMap(map, dir + "/map");
  return true;
}

std::string SlamNode::CountersReport() const {
  const SlamCounters& c = slam_.counters();
  std::ostringstream out;
  out << "odometry " << c.odometry_received << " received; scans " << c.scans_received
      << " received, " << c.scans_processed << " processed, " << c.invalid_beams
      << " invalid beams ignored\n"
      << "graph: " << slam_.graph().nodes.size() << " keyframes, " << slam_.graph().edges.size()
      << " edges, revision " << slam_.graph_revision() << "; loop closures "
      << c.loop_closures_accepted << " accepted, " << c.loop_closures_rejected << " rejected ("
      << c.loop_closures_removed << " removed after optimization); " << c.optimizations
      << " optimizations; " << c.matches_low_response << " low-response matches; "
      << c.keyframes_not_mapped << " keyframes explained by the map (graph only); "
      << c.odometry_rebases << " odometry rebases; " << c.scan_clock_resyncs
      << " scan clock resyncs\n"
      << "published: " << poses_published_ << " poses, " << graphs_published_ << " graphs, "
      << maps_published_ << " maps\n"
      << "dropped by slam: " << c.dropped_total();
  for (int i = 0; i < static_cast<int>(DropReason::kCount); ++i) {
    out << (i == 0 ? " (" : ", ") << DropReasonName(static_cast<DropReason>(i)) << " "
        << c.dropped[i];
  }
  out << ")\n";
  for (const char* channel : {channels::kOdometry, channels::kLidarScan}) {
    const ChannelStats& s = subscriptions_.stats(channel);
    out << channel << ": " << s.received << " handled, " << s.decode_failures
        << " decode failures, " << s.rejected << " rejected, " << s.handler_errors
        << " handler errors\n";
  }
  return out.str();
}

}  // namespace aslam
