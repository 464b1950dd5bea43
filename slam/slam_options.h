#pragma once

// Every option of the SLAM component in one struct (docs/architecture.md §7), loaded from
// the `slam:` config section by slam_config.h.

#include "common/stream_clock.h"
#include "slam/occupancy_mapper.h"
#include "slam/pose_graph_optimizer.h"
#include "slam/scan_matcher.h"

namespace aslam {

struct KeyframeOptions {
  double travel_m = 0.3;       // a new keyframe after this much odometry travel...
  double rotation_rad = 0.35;  // ...or this much rotation
};

// A keyframe whose scan the map already explains (the robot passing rooms and corridors it
// has mapped) joins the pose graph but not the map, so re-rendering after loop closures and
// every SLAM_MAP consumer scale with what is new, not with how often the robot passes by.
// The graph does not depend on the map: poses and closures are the same either way.
struct MapThinningOptions {
  bool enabled = true;
  // Explained: inserting the scan would observe at most this much never-observed area.
  double max_revealed_area_m2 = 0.01;
  // Mapped anyway this far (odometry travel or rotation) from the last mapped keyframe.
  double max_travel_m = 1.0;
  double max_rotation_rad = 0.7;
};

struct FrontEndOptions {
  double point_spacing_m = 0.05;  // scan points thinned to this spacing before matching
  int local_map_keyframes = 10;   // recent keyframes the new one is matched against
  SearchWindow window{0.3, 0.35};
  // Below this response the match is not trusted and odometry alone places the keyframe.
  double min_response = 0.3;
  // Odometry's uncertainty per keyframe step, as standard deviations: fused with every scan
  // match (it decides where the scan cannot, e.g. along a corridor longer than the lidar's
  // range) and the information of an odometry-only sequential edge.
  double odometry_sigma_m = 0.05;
  double odometry_sigma_rad = 0.03;
};

struct LoopClosureOptions {
  bool enabled = true;
  double search_radius_m = 4.0;     // candidates lie this close to the new keyframe...
  int recent_chain_keyframes = 30;  // ...and are not among its newest predecessors
  int neighbour_keyframes = 5;      // the candidate's local map: it and this many either side
  SearchWindow window{2.0, 0.5};
  double min_response = 0.55;  // a weaker match is rejected
  // At most one attempt per this many keyframes, so one revisit is not closed over and over.
  int keyframes_between_attempts = 5;
  // After optimization, a loop-closure edge whose chi-square exceeds this tears the
  // graph: it is removed and the graph re-optimized.
  double max_chi_square = 25.0;
  // After optimization, keyframes whose beams moved farther than this from where
  // the map has them (bound: translation + beam reach x rotation) are re-rendered,
  // only where they cover; 0 re-renders every keyframe that moved at all.
  double map_rerender_tolerance_m = 0.01;
};

struct InputOptions {
  int min_valid_points = 40;          // scans with fewer valid returns are dropped
  double max_linear_speed_mps = 3.0;  // odometry faster than this between messages is a jump
  double max_angular_speed_radps = 8.0;
  double odometry_buffer_s = 5.0;  // odometry kept to look up the pose at a scan's time
  // A message later than this after the previous one of its stream is a time jump.
  double max_time_gap_s = kDefaultMaxTimeGapS;
  // A message out of line with its stream (time backwards, a time jump, odometry faster than
  // the bounds above) is held back; this many in a row that agree with one another start a
  // new stream, so one bad stamp is dropped and a real reset is followed.
  int resync_messages = kDefaultResyncMessages;
  // A swept scan (with beam times) is motion-compensated with odometry at each beam's time
  // before it becomes a keyframe (slam/scan_deskew.h); false keeps it as measured.
  bool deskew = true;
  // Odometry is extrapolated at its last velocities at most this far past its newest sample
  // for the last beams of a sweep.
  double deskew_max_extrapolation_s = 0.1;
};

struct SlamOptions {
  KeyframeOptions keyframe;
  MapThinningOptions map_thinning;
  FrontEndOptions front_end;
  LoopClosureOptions loop_closure;
  ScanMatcherOptions scan_matcher;
  PoseGraphOptimizerOptions optimizer;
  OccupancyMapperOptions mapper;
  InputOptions input;
};

}  // namespace aslam
