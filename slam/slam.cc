#include "slam/slam.h"

#include "slam/scan_deskew.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace aslam {
namespace {

bool IsFinite(const Pose2d& pose) {
  return std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.yaw_rad);
}

double Norm(const Pose2d& pose) { return std::hypot(pose.x_m, pose.y_m); }

// How far from the base a beam of `scan` reaches into the map: the farthest
// valid return (or no-return clearing) plus the sensor's offset.
double BeamReachM(const LidarScan& scan, double no_return_clear_m) {
  double reach_m = no_return_clear_m;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    if (scan.IsValidReturn(i)) reach_m = std::max(reach_m, static_cast<double>(scan.range_m[i]));
  }
  return reach_m + std::hypot(scan.sensor_pose.x_m, scan.sensor_pose.y_m);
}

void Require(bool condition, const std::string& field, double value, const char* rule) {
  if (!condition) {
    throw std::invalid_argument(field + " = " + std::to_string(value) + ": " + rule);
  }
}

}  // namespace

const char* DropReasonName(DropReason reason) {
  switch (reason) {
    case DropReason::kOdometryTimeBackwards: return "odometry_time_backwards";
    case DropReason::kOdometryTimeJump: return "odometry_time_jump";
    case DropReason::kOdometryJump: return "odometry_jump";
    case DropReason::kOdometryNotFinite: return "odometry_not_finite";
    case DropReason::kScanTimeBackwards: return "scan_time_backwards";
    case DropReason::kScanTimeJump: return "scan_time_jump";
    case DropReason::kScanBeforeOdometry: return "scan_before_odometry";
    case DropReason::kScanTooFewPoints: return "scan_too_few_points";
    case DropReason::kScanMalformed: return "scan_malformed";
    case DropReason::kCount: break;
  }
  return "unknown";
}

int64_t SlamCounters::dropped_total() const {
  int64_t total = 0;
  for (const int64_t n : dropped) total += n;
  return total;
}

void ValidateSlamOptions(const SlamOptions& o) {
  Require(o.keyframe.travel_m > 0, "keyframe.travel_m", o.keyframe.travel_m, "must be > 0");
  Require(o.keyframe.rotation_rad > 0, "keyframe.rotation_rad", o.keyframe.rotation_rad,
          "must be > 0");
  const MapThinningOptions& t = o.map_thinning;
  Require(t.max_revealed_area_m2 >= 0, "map_thinning.max_revealed_area_m2", t.max_revealed_area_m2,
          "must be >= 0");
  Require(t.max_travel_m >= 0, "map_thinning.max_travel_m", t.max_travel_m, "must be >= 0");
  Require(t.max_rotation_rad >= 0, "map_thinning.max_rotation_rad", t.max_rotation_rad,
          "must be >= 0");
  const FrontEndOptions& f = o.front_end;
  Require(f.point_spacing_m >= 0, "front_end.point_spacing_m", f.point_spacing_m, "must be >= 0");
  Require(f.local_map_keyframes >= 1, "front_end.local_map_keyframes", f.local_map_keyframes,
          "must be >= 1");
  Require(f.window.linear_m > 0, "front_end.window.linear_m", f.window.linear_m, "must be > 0");
  Require(f.window.angular_rad > 0, "front_end.window.angular_rad", f.window.angular_rad,
          "must be > 0");
  Require(f.min_response >= 0 && f.min_response <= 1, "front_end.min_response", f.min_response,
          "must be in [0, 1]");
  Require(f.odometry_sigma_m > 0, "front_end.odometry_sigma_m", f.odometry_sigma_m, "must be > 0");
  Require(f.odometry_sigma_rad > 0, "front_end.odometry_sigma_rad", f.odometry_sigma_rad,
          "must be > 0");
  const LoopClosureOptions& l = o.loop_closure;
  Require(l.search_radius_m > 0, "loop_closure.search_radius_m", l.search_radius_m, "must be > 0");
  Require(l.recent_chain_keyframes >= 1, "loop_closure.recent_chain_keyframes",
          l.recent_chain_keyframes, "must be >= 1");
  Require(l.neighbour_keyframes >= 0, "loop_closure.neighbour_keyframes", l.neighbour_keyframes,
          "must be >= 0");
  Require(l.window.linear_m > 0, "loop_closure.window.linear_m", l.window.linear_m, "must be > 0");
  Require(l.window.angular_rad > 0, "loop_closure.window.angular_rad", l.window.angular_rad,
          "must be > 0");
  Require(l.min_response >= 0 && l.min_response <= 1, "loop_closure.min_response", l.min_response,
          "must be in [0, 1]");
  Require(l.keyframes_between_attempts >= 1, "loop_closure.keyframes_between_attempts",
          l.keyframes_between_attempts, "must be >= 1");
  Require(l.max_chi_square > 0, "loop_closure.max_chi_square", l.max_chi_square, "must be > 0");
  Require(l.map_rerender_tolerance_m >= 0, "loop_closure.map_rerender_tolerance_m",
          l.map_rerender_tolerance_m, "must be >= 0");
  const InputOptions& in = o.input;
  Require(in.min_valid_points >= 3, "input.min_valid_points", in.min_valid_points, "must be >= 3");
  Require(in.max_linear_speed_mps > 0, "input.max_linear_speed_mps", in.max_linear_speed_mps,
          "must be > 0");
  Require(in.max_angular_speed_radps > 0, "input.max_angular_speed_radps",
          in.max_angular_speed_radps, "must be > 0");
  Require(in.odometry_buffer_s > 0, "input.odometry_buffer_s", in.odometry_buffer_s, "must be > 0");
  Require(in.max_time_gap_s > 0, "input.max_time_gap_s", in.max_time_gap_s, "must be > 0");
  Require(in.resync_messages >= 2, "input.resync_messages", in.resync_messages, "must be >= 2");
  const PoseGraphOptimizerOptions& opt = o.optimizer;
  Require(opt.max_iterations >= 1, "optimizer.max_iterations", opt.max_iterations, "must be >= 1");
  Require(opt.function_tolerance > 0, "optimizer.function_tolerance", opt.function_tolerance,
          "must be > 0");
  Require(opt.num_threads >= 1, "optimizer.num_threads", opt.num_threads, "must be >= 1");
  ValidateScanMatcherOptions(o.scan_matcher);
  OccupancyMapper check_mapper(o.mapper);  // throws std::invalid_argument naming the field
}

namespace {
const SlamOptions& CheckedOrAbort(const SlamOptions& options) {
  try {
    ValidateSlamOptions(options);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "Slam: invalid options (validate at load time): %s\n", e.what());
    std::abort();
  }
  return options;
}
}  // namespace

Slam::Slam(SlamOptions options)
    : options_(CheckedOrAbort(options)),
      matcher_(options_.scan_matcher),
      optimizer_(options_.optimizer),
      map_(options_.mapper),
      scan_clock_(std::llround(options_.input.max_time_gap_s * 1e6),
                  options_.input.resync_messages) {}

void Slam::Restore(SlamSnapshot snapshot) {
  if (!keyframes_.empty() || counters_.odometry_received > 0 || counters_.scans_received > 0) {
    throw std::invalid_argument("Slam::Restore: only before any input");
  }
  const std::size_t n = snapshot.keyframes.size();
  if (snapshot.graph.nodes.size() != n) {
    throw std::invalid_argument("journal: " + std::to_string(n) + " keyframes but " +
                                std::to_string(snapshot.graph.nodes.size()) + " graph nodes");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (snapshot.keyframes[i].id != static_cast<int>(i) ||
        snapshot.graph.nodes[i].id != static_cast<int>(i)) {
      throw std::invalid_argument("journal: keyframe " + std::to_string(i) + " has id " +
                                  std::to_string(snapshot.keyframes[i].id) + ": ids must run 0..");
    }
    if (!IsFinite(snapshot.graph.nodes[i].pose)) {
      throw std::invalid_argument("journal: keyframe " + std::to_string(i) + " pose not finite");
    }
  }
  for (const PoseGraphEdge& e : snapshot.graph.edges) {
    if (e.from_id < 0 || e.to_id < 0 || e.from_id >= static_cast<int>(n) ||
        e.to_id >= static_cast<int>(n)) {
      throw std::invalid_argument("journal: an edge " + std::to_string(e.from_id) + " -> " +
                                  std::to_string(e.to_id) + " names a missing keyframe");
    }
  }
  graph_ = std::move(snapshot.graph);
  for (KeyframeRecord& record : snapshot.keyframes) {
    const Pose2d& pose = graph_.nodes[record.id].pose;
    auto points = std::make_shared<PointCloud2d>(
        ScanToPoints(record.scan, options_.front_end.point_spacing_m));
    const double reach_m = BeamReachM(record.scan, options_.mapper.no_return_clear_m);
    keyframes_.push_back(Keyframe{record.utime, record.odom_pose, std::move(points),
                                  std::move(record.scan), pose, -1, reach_m, record.in_map});
    Keyframe& keyframe = keyframes_.back();
    if (keyframe.in_map) keyframe.submap = map_.InsertScan(pose, keyframe.scan);
  }
  const SlamState& state = snapshot.state;
  counters_ = state.counters;
  last_closure_attempt_node_ = state.last_closure_attempt_node;
  last_mapped_odom_pose_ = state.last_mapped_odom_pose;
  odometry_correction_ = state.odometry_correction;
  resumed_ = n > 0;
  ++graph_revision_;
  ++map_revision_;
}

bool Slam::AddOdometry(const Odometry& raw) {
  if (!IsFinite(raw.pose)) {
    Drop(DropReason::kOdometryNotFinite);
    return false;
  }
  const InputOptions& in = options_.input;
  const int64_t max_gap_us = std::llround(in.max_time_gap_s * 1e6);
  // In line: later, by at most the time gap, and no faster than the physical bound
  // (plus a small slack for noise).
  auto follows = [&](const Odometry& from, const Odometry& to) {
    const int64_t dt_us = to.utime - from.utime;
    if (dt_us <= 0 || dt_us > max_gap_us) return false;
    const Pose2d delta = from.pose.Between(to.pose);
    return Norm(delta) <= in.max_linear_speed_mps * dt_us * 1e-6 + 0.05 &&
           std::abs(delta.yaw_rad) <= in.max_angular_speed_radps * dt_us * 1e-6 + 0.05;
  };
  if (resumed_ && !last_raw_odometry_) {
    // The first odometry after a restore: the robot stood still while SLAM was down (the
    // navigator stops without poses), so motion since the last keyframe beyond the bounds,
    // over however long the gap, means the odometry itself restarted: rebase onto it.
    const Keyframe& last = keyframes_.back();
    const double dt_s = std::max<int64_t>(raw.utime - last.utime, 0) * 1e-6;
    const Pose2d delta = last.odom_pose.Between(odometry_correction_.Compose(raw.pose));
    if (Norm(delta) > in.max_linear_speed_mps * dt_s + 0.05 ||
        std::abs(delta.yaw_rad) > in.max_angular_speed_radps * dt_s + 0.05) {
      odometry_correction_ = last.odom_pose.Compose(raw.pose.Inverse());
      ++counters_.odometry_rebases;
    }
    AcceptOdometry(raw);
    return true;
  }
  if (!last_raw_odometry_ || follows(*last_raw_odometry_, raw)) {
    odometry_candidates_.clear();
    AcceptOdometry(raw);
    return true;
  }
  if (!odometry_candidates_.empty() && !follows(odometry_candidates_.back(), raw)) {
    odometry_candidates_.clear();
  }
  odometry_candidates_.push_back(raw);
  if (static_cast<int>(odometry_candidates_.size()) < in.resync_messages) {
    const int64_t dt_us = raw.utime - last_raw_odometry_->utime;
    Drop(dt_us <= 0           ? DropReason::kOdometryTimeBackwards
         : dt_us > max_gap_us ? DropReason::kOdometryTimeJump
                              : DropReason::kOdometryJump);
    return false;
  }
  // A new stream (the odometry was reset, or its clock stepped): rebase so that no motion
  // is seen across the break, and forget the old stream's samples.
  const std::vector<Odometry> stream = std::move(odometry_candidates_);
  odometry_candidates_.clear();
  odometry_correction_ =
      odometry_correction_.Compose(last_raw_odometry_->pose).Compose(stream.front().pose.Inverse());
  odometry_.clear();
  ++counters_.odometry_rebases;
  for (const Odometry& message : stream) AcceptOdometry(message);
  return true;
}

void Slam::AcceptOdometry(const Odometry& raw) {
  last_raw_odometry_ = raw;
  Odometry corrected = raw;
  corrected.pose = odometry_correction_.Compose(raw.pose);
  odometry_.push_back(corrected);
  const int64_t keep_us = static_cast<int64_t>(options_.input.odometry_buffer_s * 1e6);
  while (odometry_.size() > 2 && odometry_.front().utime < raw.utime - keep_us) {
    odometry_.pop_front();
  }
  ++counters_.odometry_received;
}

LidarScan Slam::Deskewed(const LidarScan& scan, const Pose2d& odom_at_scan) const {
  if (!options_.input.deskew || scan.beam_time_s.empty()) return scan;
  const Pose2d odom_at_scan_inverse = odom_at_scan.Inverse();
  const Odometry& newest = odometry_.back();
  const int64_t max_extrapolation_us =
      std::llround(options_.input.deskew_max_extrapolation_s * 1e6);
  return DeskewScan(scan, [&](double seconds_after_utime) {
    const int64_t utime = scan.utime + std::llround(seconds_after_utime * 1e6);
    // The last beams of a sweep may postdate the newest odometry by a sample period.
    if (utime > newest.utime && utime - newest.utime <= max_extrapolation_us) {
      const double dt_s = (utime - newest.utime) * 1e-6;
      const Pose2d step{newest.linear_velocity_mps * dt_s, 0.0,
                        newest.angular_velocity_radps * dt_s};
      return odom_at_scan_inverse * newest.pose * step;
    }
    const std::optional<Pose2d> odom = OdometryAt(utime);
    return odom ? odom_at_scan_inverse * *odom : Pose2d{};
  });
}

std::optional<Pose2d> Slam::OdometryAt(int64_t utime) const {
  if (odometry_.empty()) return std::nullopt;
  // The newest sample at or before `utime`, interpolated toward the next one.
  auto after = std::upper_bound(odometry_.begin(), odometry_.end(), utime,
                                [](int64_t t, const Odometry& o) { return t < o.utime; });
  if (after == odometry_.begin()) {
    // Older than every sample: usable only if very close to the oldest.
    if (odometry_.front().utime - utime > 200000) return std::nullopt;
    return odometry_.front().pose;
  }
  const Odometry& before = *std::prev(after);
  if (after == odometry_.end()) {
    // Newer than every sample: the latest pose, unless the odometry has gone quiet.
    if (utime - before.utime > std::llround(options_.input.max_time_gap_s * 1e6)) {
      return std::nullopt;
    }
    return before.pose;
  }
  if (before.utime == utime) return before.pose;
  const double fraction =
      static_cast<double>(utime - before.utime) / static_cast<double>(after->utime - before.utime);
  return Interpolate(before.pose, after->pose, fraction);
}

ScanUpdate Slam::AddScan(const LidarScan& scan) {
  ScanUpdate update;
  ++counters_.scans_received;
  if (scan.range_m.empty() || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad) || scan.angle_increment_rad == 0.0 ||
      !std::isfinite(scan.range_max_m) || !(scan.range_max_m > scan.range_min_m) ||
      !IsFinite(scan.sensor_pose)) {
    Drop(DropReason::kScanMalformed);
    return update;
  }
  switch (scan_clock_.Offer(scan.utime)) {
    case StreamClock::Verdict::kBackwards: Drop(DropReason::kScanTimeBackwards); return update;
    case StreamClock::Verdict::kJump: Drop(DropReason::kScanTimeJump); return update;
    case StreamClock::Verdict::kResynced: ++counters_.scan_clock_resyncs; break;
    case StreamClock::Verdict::kInLine:
    case StreamClock::Verdict::kLate: break;  // late: only with a tolerance, which scans have not
  }
  const std::optional<Pose2d> odom_pose = OdometryAt(scan.utime);
  if (!odom_pose) {
    Drop(DropReason::kScanBeforeOdometry);
    return update;
  }
  int valid_returns = 0;
  int64_t invalid_beams = 0;
  for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
    const float r = scan.range_m[i];
    if (!std::isfinite(r) || r < 0.0f) ++invalid_beams;
    if (scan.IsValidReturn(i)) ++valid_returns;
  }
  counters_.invalid_beams += invalid_beams;
  if (valid_returns < options_.input.min_valid_points) {
    Drop(DropReason::kScanTooFewPoints);
    return update;
  }
  ++counters_.scans_processed;
  update.accepted = true;

  const bool first = keyframes_.empty();
  if (!first) {
    const Pose2d since_keyframe = keyframes_.back().odom_pose.Between(*odom_pose);
    if (Norm(since_keyframe) < options_.keyframe.travel_m &&
        std::abs(since_keyframe.yaw_rad) < options_.keyframe.rotation_rad) {
      update.pose.pose = graph_.nodes.back().pose.Compose(since_keyframe);
    } else {
      AddKeyframe(Deskewed(scan, *odom_pose), *odom_pose, &update);
    }
  } else {
    AddKeyframe(Deskewed(scan, *odom_pose), *odom_pose, &update);
  }
  if (update.keyframe_added) update.pose.pose = graph_.nodes.back().pose;
  update.pose.utime = scan.utime;
  if (last_raw_odometry_) {
    update.pose.linear_velocity_mps = last_raw_odometry_->linear_velocity_mps;
    update.pose.angular_velocity_radps = last_raw_odometry_->angular_velocity_radps;
  }
  latest_pose_ = update.pose;
  return update;
}

Eigen::Matrix3d Slam::FuseWithOdometry(const ScanMatchResult& match, const Pose2d& prediction,
                                       Pose2d* fused) const {
  // Odometry's step covariance, along and across the predicted heading, in map axes.
  const double c = std::cos(prediction.yaw_rad), s = std::sin(prediction.yaw_rad);
  Eigen::Matrix3d rotation;
  rotation << c, -s, 0, s, c, 0, 0, 0, 1;
  const double sigma_m = options_.front_end.odometry_sigma_m;
  const double sigma_rad = options_.front_end.odometry_sigma_rad;
  const Eigen::Matrix3d odometry_information =
      rotation *
      Eigen::Vector3d(1.0 / (sigma_m * sigma_m), 1.0 / (sigma_m * sigma_m),
                      1.0 / (sigma_rad * sigma_rad))
          .asDiagonal() *
      rotation.transpose();
  const Eigen::Matrix3d match_information = match.covariance.inverse();
  const Eigen::Matrix3d covariance = (match_information + odometry_information).inverse();
  // The information-weighted mean: prediction + Σ·I_match·(match − prediction).
  const Eigen::Vector3d to_match(match.refined_pose.x_m - prediction.x_m,
                                 match.refined_pose.y_m - prediction.y_m,
                                 WrapAngle(match.refined_pose.yaw_rad - prediction.yaw_rad));
  const Eigen::Vector3d step = covariance * match_information * to_match;
  *fused =
      Pose2d{prediction.x_m + step.x(), prediction.y_m + step.y(), prediction.yaw_rad + step.z()};
  return covariance;
}

Eigen::Matrix3d Slam::EdgeInformation(const Pose2d& from_pose,
                                      const Eigen::Matrix3d& covariance_map) const {
  // The measurement's translation is expressed in the `from` frame: rotate the
  // map-axes covariance by R(from.yaw)ᵀ (yaw unaffected).
  const double c = std::cos(from_pose.yaw_rad), s = std::sin(from_pose.yaw_rad);
  Eigen::Matrix3d rotation_t;
  rotation_t << c, s, 0, -s, c, 0, 0, 0, 1;
  Eigen::Matrix3d covariance = rotation_t * covariance_map * rotation_t.transpose();
  covariance = 0.5 * (covariance + covariance.transpose());
  Eigen::Matrix3d information = covariance.inverse();
  return 0.5 * (information + information.transpose());
}

void Slam::AddKeyframe(const LidarScan& scan, const Pose2d& odom_pose, ScanUpdate* update) {
  auto points =
      std::make_shared<PointCloud2d>(ScanToPoints(scan, options_.front_end.point_spacing_m));
  const int id = static_cast<int>(keyframes_.size());
  std::optional<PoseGraphEdge> sequential_edge;
  Pose2d pose;  // the first keyframe anchors "map"
  if (id > 0) {
    const Pose2d& previous_pose = graph_.nodes.back().pose;
    const Pose2d prediction = previous_pose.Compose(keyframes_.back().odom_pose.Between(odom_pose));
    std::vector<PosedPoints> local;
    const int first_local = std::max(0, id - options_.front_end.local_map_keyframes);
    for (int i = first_local; i < id; ++i) {
      local.push_back(PosedPoints{graph_.nodes[i].pose, keyframes_[i].points});
    }
    const CorrelationMap local_map(local, options_.scan_matcher);
    const ScanMatchResult match =
        matcher_.Match(local_map, *points, prediction, options_.front_end.window);
    PoseGraphEdge edge;
    edge.from_id = id - 1;
    edge.to_id = id;
    edge.kind = EdgeKind::kOdometry;
    if (match.found && match.response >= options_.front_end.min_response) {
      // The match's covariance is large along what the scan cannot see (a corridor longer
      // than the lidar's range): there the odometry prediction decides.
      const Eigen::Matrix3d covariance = FuseWithOdometry(match, prediction, &pose);
      edge.information = EdgeInformation(previous_pose, covariance);
      latest_covariance_ = covariance;
    } else {
      ++counters_.matches_low_response;
      pose = prediction;
      const double var_m =
          options_.front_end.odometry_sigma_m * options_.front_end.odometry_sigma_m;
      const double var_rad =
          options_.front_end.odometry_sigma_rad * options_.front_end.odometry_sigma_rad;
      edge.information = Eigen::Vector3d(1.0 / var_m, 1.0 / var_m, 1.0 / var_rad).asDiagonal();
      latest_covariance_ = Eigen::Vector3d(var_m, var_m, var_rad).asDiagonal();
    }
    pose.yaw_rad = WrapAngle(pose.yaw_rad);
    edge.measurement = previous_pose.Between(pose);
    graph_.edges.push_back(edge);
    sequential_edge = edge;
  }
  graph_.nodes.push_back(PoseGraphNode{id, scan.utime, pose});
  keyframes_.push_back(Keyframe{scan.utime, odom_pose, std::move(points), scan, pose, -1,
                                BeamReachM(scan, options_.mapper.no_return_clear_m)});
  Keyframe& keyframe = keyframes_.back();
  if (MapExplains(keyframe, pose)) {
    ++counters_.keyframes_not_mapped;
  } else {
    keyframe.submap = map_.InsertScan(pose, scan);
    keyframe.in_map = true;
    last_mapped_odom_pose_ = odom_pose;
    ++map_revision_;
    update->keyframe_mapped = true;
  }
  ++graph_revision_;
  update->keyframe_added = true;
  update->graph_changed = true;
  if (journal_) {
    journal_->OnKeyframe(KeyframeRecord{id, scan.utime, odom_pose, pose, keyframe.in_map, scan},
                         sequential_edge);
  }

  TryLoopClosure(id, update);
  if (journal_) journal_->OnState(State());
}

SlamSnapshot Slam::Snapshot() const {
  SlamSnapshot snapshot;
  snapshot.graph = graph_;
  snapshot.state = State();
  snapshot.keyframes.reserve(keyframes_.size());
  for (std::size_t i = 0; i < keyframes_.size(); ++i) {
    const Keyframe& k = keyframes_[i];
    snapshot.keyframes.push_back(KeyframeRecord{static_cast<int>(i), k.utime, k.odom_pose,
                                                graph_.nodes[i].pose, k.in_map, k.scan});
  }
  return snapshot;
}

SlamState Slam::State() const {
  return SlamState{counters_, last_closure_attempt_node_, last_mapped_odom_pose_,
                   odometry_correction_};
}

void Slam::EraseEdge(std::size_t index) {
  if (journal_) journal_->OnEdgeRemoved(graph_.edges[index]);
  graph_.edges.erase(graph_.edges.begin() + index);
}

bool Slam::MapExplains(const Keyframe& keyframe, const Pose2d& pose) const {
  const MapThinningOptions& t = options_.map_thinning;
  if (!t.enabled || !last_mapped_odom_pose_) return false;
  const Pose2d since_mapped = last_mapped_odom_pose_->Between(keyframe.odom_pose);
  if (std::hypot(since_mapped.x_m, since_mapped.y_m) >= t.max_travel_m ||
      std::abs(since_mapped.yaw_rad) >= t.max_rotation_rad) {
    return false;
  }
  const double cell_area_m2 = options_.mapper.resolution_m * options_.mapper.resolution_m;
  return map_.CountRevealedCells(pose, keyframe.scan) * cell_area_m2 <= t.max_revealed_area_m2;
}

void Slam::TryLoopClosure(int node_id, ScanUpdate* update) {
  const LoopClosureOptions& lc = options_.loop_closure;
  if (!lc.enabled || node_id - last_closure_attempt_node_ < lc.keyframes_between_attempts) return;
  const int newest_candidate = node_id - lc.recent_chain_keyframes - 1;
  if (newest_candidate < 0) return;
  const Pose2d& pose = graph_.nodes[node_id].pose;
  int candidate = -1;
  double best_distance_m = lc.search_radius_m;
  for (int j = 0; j <= newest_candidate; ++j) {
    const double d =
        std::hypot(graph_.nodes[j].pose.x_m - pose.x_m, graph_.nodes[j].pose.y_m - pose.y_m);
    if (d < best_distance_m) {
      best_distance_m = d;
      candidate = j;
    }
  }
  if (candidate < 0) return;
  last_closure_attempt_node_ = node_id;

  std::vector<PosedPoints> local;
  const int last = std::min(newest_candidate, candidate + lc.neighbour_keyframes);
  for (int i = std::max(0, candidate - lc.neighbour_keyframes); i <= last; ++i) {
    local.push_back(PosedPoints{graph_.nodes[i].pose, keyframes_[i].points});
  }
  const CorrelationMap candidate_map(local, options_.scan_matcher);
  const ScanMatchResult match =
      matcher_.Match(candidate_map, *keyframes_[node_id].points, pose, lc.window);
  if (!match.found || match.response < lc.min_response) {
    ++counters_.loop_closures_rejected;
    ++update->loop_closures_rejected;
    return;
  }
  const Pose2d& candidate_pose = graph_.nodes[candidate].pose;
  PoseGraphEdge edge;
  edge.from_id = candidate;
  edge.to_id = node_id;
  edge.kind = EdgeKind::kLoopClosure;
  edge.measurement = candidate_pose.Between(match.refined_pose);
  edge.information = EdgeInformation(candidate_pose, match.covariance);
  graph_.edges.push_back(edge);
  if (journal_) journal_->OnLoopClosureAdded(edge);
  if (OptimizeAndCheck(graph_.edges.size() - 1, update)) {
    ++counters_.loop_closures_accepted;
    ++update->loop_closures_accepted;
  } else {
    ++counters_.loop_closures_rejected;
    ++update->loop_closures_rejected;
  }
  if (map_drift_m() > lc.map_rerender_tolerance_m) {
    map_stale_ = true;
    ++map_revision_;
    update->map_invalidated = true;
  }
}

double Slam::DriftM(std::size_t keyframe) const {
  if (!keyframes_[keyframe].in_map) return 0.0;  // nothing of it to move
  const Pose2d& mapped = keyframes_[keyframe].mapped_pose;
  const Pose2d& now = graph_.nodes[keyframe].pose;
  // A beam end at distance q from the base moves by at most |dt| + q |dyaw|.
  return std::hypot(now.x_m - mapped.x_m, now.y_m - mapped.y_m) +
         keyframes_[keyframe].beam_reach_m * std::abs(WrapAngle(now.yaw_rad - mapped.yaw_rad));
}

double Slam::map_drift_m() const {
  double worst_m = 0.0;
  for (std::size_t i = 0; i < keyframes_.size(); ++i) worst_m = std::max(worst_m, DriftM(i));
  return worst_m;
}

bool Slam::OptimizeAndCheck(std::size_t new_edge, ScanUpdate* update) {
  std::vector<Pose2d> before;
  before.reserve(graph_.nodes.size());
  for (const PoseGraphNode& node : graph_.nodes) before.push_back(node.pose);
  auto restore = [&] {
    for (std::size_t i = 0; i < before.size(); ++i) graph_.nodes[i].pose = before[i];
  };
  bool new_edge_alive = true;
  // Each pass removes the worst closure that tears the graph and re-optimizes without it.
  for (int removals = 0;; ++removals) {
    const OptimizationSummary summary = optimizer_.Optimize(&graph_);
    ++counters_.optimizations;
    update->graph_optimized = true;
    if (!summary.usable) {
      restore();
      if (new_edge_alive) EraseEdge(new_edge);
      new_edge_alive = false;
      break;
    }
    std::size_t worst = graph_.edges.size();
    double worst_chi_square = options_.loop_closure.max_chi_square;
    for (std::size_t e = 0; e < graph_.edges.size(); ++e) {
      if (graph_.edges[e].kind != EdgeKind::kLoopClosure) continue;
      const double chi_square = EdgeChiSquare(graph_, graph_.edges[e]);
      if (chi_square > worst_chi_square) {
        worst_chi_square = chi_square;
        worst = e;
      }
    }
    if (worst == graph_.edges.size() || removals == 3) break;
    EraseEdge(worst);
    ++counters_.loop_closures_removed;
    if (new_edge_alive && worst == new_edge) {
      new_edge_alive = false;
    } else {
      // An earlier closure no longer fits: it leaves the graph and the accepted count.
      if (new_edge_alive && worst < new_edge) --new_edge;
      --counters_.loop_closures_accepted;
      ++counters_.loop_closures_rejected;
    }
    restore();
  }
  ++graph_revision_;
  update->graph_changed = true;
  if (journal_) journal_->OnOptimized(graph_.nodes);
  return new_edge_alive;
}

OccupancyGrid Slam::RenderMap() {
  if (map_stale_) RerenderDriftedKeyframes();
  return map_.Render();
}

void Slam::RerenderDriftedKeyframes() {
  map_stale_ = false;
  const double tolerance_m = options_.loop_closure.map_rerender_tolerance_m;
  // Each submap's keyframes, in insertion order; a submap with one drifted keyframe is rebuilt.
  std::vector<std::vector<std::size_t>> members(map_.num_submaps());
  std::vector<bool> drifted(members.size(), false);
  for (std::size_t i = 0; i < keyframes_.size(); ++i) {
    const int submap = keyframes_[i].submap;
    if (submap < 0) continue;
    members[submap].push_back(i);
    if (!drifted[submap] && DriftM(i) > tolerance_m) drifted[submap] = true;
  }
  std::vector<SubmapMap::PosedScan> scans;
  for (std::size_t submap = 0; submap < members.size(); ++submap) {
    if (!drifted[submap]) continue;
    scans.clear();
    for (const std::size_t i : members[submap]) {
      scans.push_back({graph_.nodes[i].pose, &keyframes_[i].scan});
      keyframes_[i].mapped_pose = graph_.nodes[i].pose;
    }
    map_.RerenderSubmap(static_cast<int>(submap), scans);
  }
}

}  // namespace aslam
