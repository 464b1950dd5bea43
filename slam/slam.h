#pragma once

// The SLAM front end: keyframes from odometry travel, each placed by
// correlative scan matching against the recent keyframes, loop closures
// against older nearby keyframes, the pose graph optimized after every
// accepted closure (and cleaned of closures that tear it), and the occupancy
// grid rendered from the keyframe poses. Pure C++: the node feeds it decoded
// messages; time comes only from their utimes.
//
// Frames: "odom" is the wheel odometry's; "map" is anchored at the first
// keyframe (its pose is the identity).

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "common/stream_clock.h"
#include "slam/occupancy_mapper.h"
#include "slam/pose_graph_optimizer.h"
#include "slam/scan_matcher.h"
#include "slam/slam_options.h"
#include "slam/submap_map.h"

namespace aslam {

// Why an input was dropped (the counters are indexed by this).
enum class DropReason : int {
  kOdometryTimeBackwards = 0,  // utime not after the previous odometry
  kOdometryTimeJump,           // utime more than input.max_time_gap_s after the previous
  kOdometryJump,               // faster than the physical bound since the previous message
  kOdometryNotFinite,
  kScanTimeBackwards,   // utime not after the previous scan
  kScanTimeJump,        // utime more than input.max_time_gap_s after the previous scan
  kScanBeforeOdometry,  // no odometry at its time to place it (none yet, or none recent)
  kScanTooFewPoints,    // fewer than min_valid_points valid returns
  kScanMalformed,       // bad geometry (non-finite angles, non-positive increment...)
  kCount
};
const char* DropReasonName(DropReason reason);

struct SlamCounters {
  int64_t odometry_received = 0;
  int64_t scans_received = 0;
  int64_t scans_processed = 0;
  // Beams with NaN, inf or negative ranges: ignored (like no return), the scan kept.
  int64_t invalid_beams = 0;
  // Out-of-line messages (input.resync_messages) that started a new stream: the odometry
  // was reset or its clock stepped. The held-back messages count as dropped when they came.
  int64_t odometry_rebases = 0;
  int64_t scan_clock_resyncs = 0;
  int64_t matches_low_response = 0;  // sequential edges that fell back to odometry
  int64_t keyframes_not_mapped = 0;  // explained by the map: graph only (map_thinning)
  int64_t loop_closures_accepted = 0;
  int64_t loop_closures_rejected = 0;  // weak match or torn graph
  int64_t loop_closures_removed =
      0;  // of those rejected: accepted by the matcher, removed after optimization
  int64_t optimizations = 0;
  std::array<int64_t, static_cast<int>(DropReason::kCount)> dropped{};
  int64_t dropped_total() const;
};

// A keyframe as the journal keeps it: enough to rebuild it without matching again.
struct KeyframeRecord {
  int id = 0;
  int64_t utime = 0;
  Pose2d odom_pose;  // odometry at the scan (rebased stream, see SlamState)
  Pose2d pose;       // in "map" when it was added (later optimizations move it)
  bool in_map = false;
  LidarScan scan;
};

// What the front end carries besides the graph and the keyframes.
struct SlamState {
  SlamCounters counters;
  int last_closure_attempt_node = -1000000;
  std::optional<Pose2d> last_mapped_odom_pose;
  Pose2d odometry_correction;  // rebased odometry = correction ⊕ raw
};

// Everything a Slam is made of; Slam::Restore continues from it.
struct SlamSnapshot {
  std::vector<KeyframeRecord> keyframes;  // keyframes[i] is graph.nodes[i]
  PoseGraph graph;
  SlamState state;
};

// Told of every change of the graph as it happens (the journal, slam_journal.h).
// Implementations must not throw: Slam is mid-update when it calls them.
class SlamJournalSink {
 public:
  virtual ~SlamJournalSink() = default;
  // `sequential_edge`: from the previous keyframe (none for the first).
  virtual void OnKeyframe(const KeyframeRecord& keyframe,
                          const std::optional<PoseGraphEdge>& sequential_edge) = 0;
  virtual void OnLoopClosureAdded(const PoseGraphEdge& edge) = 0;
  virtual void OnEdgeRemoved(const PoseGraphEdge& edge) = 0;
  virtual void OnOptimized(const std::vector<PoseGraphNode>& nodes) = 0;
  virtual void OnState(const SlamState& state) = 0;  // after each keyframe
};

// What one scan changed.
struct ScanUpdate {
  bool accepted = false;  // false: dropped (see counters)
  StampedPose pose;       // the base in "map" at the scan's time
  bool keyframe_added = false;
  bool keyframe_mapped = false;  // ...and inserted into the map (see map_thinning)
  int loop_closures_accepted = 0;
  int loop_closures_rejected = 0;
  bool graph_changed = false;  // nodes, edges or poses changed
  bool graph_optimized = false;
  // Optimization moved some keyframe beyond loop_closure.map_rerender_tolerance_m:
  // the next RenderMap() re-inserts those keyframes at their optimized poses (done
  // there, not per scan), re-rendering the cells they cover from every keyframe there.
  bool map_invalidated = false;
};

class Slam {
 public:
  // Aborts on invalid options: load them through slam_config.h, which validates.
  explicit Slam(SlamOptions options);

  // Continues from `snapshot` (a journal read back): same keyframe ids, poses and "map"
  // frame; the map is rendered from the keyframes. Only before any input; throws
  // std::invalid_argument naming what is inconsistent.
  void Restore(SlamSnapshot snapshot);
  // What Restore would need to continue from here: the keyframes at their current poses,
  // the graph and the front end's state.
  SlamSnapshot Snapshot() const;
  // Every later change of the graph goes to `sink` (not owned; nullptr: none).
  void set_journal(SlamJournalSink* sink) { journal_ = sink; }

  // Returns false when the message is dropped (counted by reason).
  bool AddOdometry(const Odometry& odometry);
  ScanUpdate AddScan(const LidarScan& scan);

  const PoseGraph& graph() const { return graph_; }
  // Increases with every change of the graph.
  int64_t graph_revision() const { return graph_revision_; }
  // Increases whenever a scan is inserted or the map is invalidated.
  int64_t map_revision() const { return map_revision_; }
  // The occupancy grid of every keyframe, each at its pose within
  // loop_closure.map_rerender_tolerance_m; first re-renders what optimization
  // moved farther.
  OccupancyGrid RenderMap();
  // The farthest any keyframe's beams lie from where the mapper has them:
  // what the map lags the graph by (0 right after a re-render).
  double map_drift_m() const;
  // The latest SLAM pose (latest keyframe ⊕ odometry since it); none before the first scan.
  const std::optional<StampedPose>& latest_pose() const { return latest_pose_; }
  const SlamCounters& counters() const { return counters_; }
  const SlamOptions& options() const { return options_; }
  // Covariance of the latest sequential match, (x, y, yaw) in "map" (identity-scaled before any).
  const Eigen::Matrix3d& latest_covariance() const { return latest_covariance_; }

 private:
  struct Keyframe {
    int64_t utime = 0;
    Pose2d odom_pose;  // odometry at the keyframe's scan
    std::shared_ptr<const PointCloud2d> points;
    LidarScan scan;      // kept to re-render the map after optimization
    Pose2d mapped_pose;  // where the map has this scan (the pose when last inserted)
    int submap = -1;     // its submap in map_ (-1: not in the map)
    double beam_reach_m = 0.0;
    bool in_map = false;  // false: explained by the map when added (map_thinning)
  };

  std::optional<Pose2d> OdometryAt(int64_t utime) const;
  // The scan motion-compensated to its utime, where odometry covers its beams (input.deskew).
  LidarScan Deskewed(const LidarScan& scan, const Pose2d& odom_at_scan) const;
  void AcceptOdometry(const Odometry& raw);
  SlamState State() const;
  // Removes graph_.edges[index], telling the journal.
  void EraseEdge(std::size_t index);
  void AddKeyframe(const LidarScan& scan, const Pose2d& odom_pose, ScanUpdate* update);
  // True when map_thinning keeps `keyframe`, at `pose`, out of the map.
  bool MapExplains(const Keyframe& keyframe, const Pose2d& pose) const;
  void TryLoopClosure(int node_id, ScanUpdate* update);
  // Rebuilds, at their graph poses, the submaps holding a keyframe whose beams drifted
  // beyond the tolerance; the other submaps stay as they are.
  void RerenderDriftedKeyframes();
  // How far keyframe `keyframe`'s beams lie from where the mapper has them.
  double DriftM(std::size_t keyframe) const;

  // Optimizes, then removes loop closures that tear the graph; returns false if
  // the closure just added (edge index `new_edge`) had to be removed.
  bool OptimizeAndCheck(std::size_t new_edge, ScanUpdate* update);
  // The keyframe's pose from the scan match and the odometry prediction, each weighted by its
  // information (front_end.odometry_sigma_*); returns the fused covariance (map axes).
  Eigen::Matrix3d FuseWithOdometry(const ScanMatchResult& match, const Pose2d& prediction,
                                   Pose2d* fused) const;
  Eigen::Matrix3d EdgeInformation(const Pose2d& from_pose,
                                  const Eigen::Matrix3d& covariance_map) const;
  void Drop(DropReason reason) { ++counters_.dropped[static_cast<int>(reason)]; }

  SlamOptions options_;
  ScanMatcher matcher_;
  PoseGraphOptimizer optimizer_;
  SubmapMap map_;

  PoseGraph graph_;
  std::vector<Keyframe> keyframes_;  // keyframes_[i] is graph_.nodes[i]
  int64_t graph_revision_ = 0;
  int64_t map_revision_ = 0;
  int last_closure_attempt_node_ = -1000000;
  bool map_stale_ = false;  // keyframes drifted beyond the tolerance since the last render
  std::optional<Pose2d> last_mapped_odom_pose_;

  // Odometry, with a correction that hides resets ("rebases") of the raw stream.
  std::deque<Odometry> odometry_;  // corrected, oldest first
  Pose2d odometry_correction_;     // corrected = correction ⊕ raw
  std::optional<Odometry> last_raw_odometry_;
  std::vector<Odometry> odometry_candidates_;  // held back: out of line with the stream
  StreamClock scan_clock_;

  std::optional<StampedPose> latest_pose_;
  SlamJournalSink* journal_ = nullptr;
  // Restored: the first odometry is checked against the last keyframe's, over any gap.
  bool resumed_ = false;
  Eigen::Matrix3d latest_covariance_ = Eigen::Matrix3d::Identity();
  SlamCounters counters_;
};

// Validates the options across components; throws std::invalid_argument naming the field.
void ValidateSlamOptions(const SlamOptions& options);

}  // namespace aslam
