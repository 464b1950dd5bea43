#pragma once

// What aslam-viewer shows, on value types (no LCM, no server): the newest map, pose, scan,
// pose graph, frontiers, utility scores, navigator and exploration state, process health,
// and the known area and mean edge D-optimality over time. Update() writes, for one page,
// the `update` frame of viewer/protocol.md holding only what changed since that page's
// last frame.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"
#include "common/sensor_types.h"
#include "frontier/frontier.h"
#include "navigation/navigator.h"
#include "procman/process_status.h"
#include "utility/exploration_manager.h"
#include "utility/goal_selector.h"

namespace aslam {

// One decision's UTILITY_SCORES: every frontier's terms.
struct ViewerScores {
  int64_t decision_id = 0;
  std::string method;
  int chosen_frontier_id = -1;
  std::vector<FrontierScore> scores;
};

// What one page has been sent so far (Update() advances it).
struct ViewerCursor {
  bool reset_pending = true;         // the next frame starts the page afresh
  std::optional<OccupancyGrid> map;  // the grid as the page has it (quantized)
  uint64_t map_version = 0;          // the model's map this page's grid was last diffed against
  uint64_t graph_version = 0;
  uint64_t graph_rewrite_version = 0;
  std::size_t graph_nodes_sent = 0;
  std::size_t graph_edges_sent = 0;
  std::size_t trail_sent = 0;  // poses since the newest keyframe already sent
  uint64_t pose_version = 0;
  uint64_t scan_version = 0;
  uint64_t frontiers_version = 0;
  std::map<int, uint64_t> frontier_cells_sent;  // id -> hash of the cells the page has
  uint64_t scores_version = 0;
  uint64_t nav_version = 0;
  uint64_t path_version = 0;
  uint64_t explore_version = 0;
  uint64_t processes_version = 0;
  std::size_t series_sent = 0;
};

class ViewerModel {
 public:
  // Side of the square map tiles sent to pages, in cells.
  static constexpr int kTileCells = 64;

  // Inputs; time is each message's utime ("map" frame throughout).
  void OnMap(const OccupancyGrid& grid, int64_t revision, int64_t utime);
  void OnPose(const StampedPose& pose);
  // Placed in "map" by the newest pose (a viewer's approximation: no interpolation).
  void OnScan(const LidarScan& scan);
  void OnGraph(const PoseGraph& graph, int64_t utime);
  void OnFrontiers(const FrontierList& frontiers);
  void OnScores(ViewerScores scores, int64_t utime);
  void OnNavStatus(const NavStatus& nav);
  void OnNavPath(std::vector<Point2d> path_m, int64_t utime);
  void OnExploreStatus(const ExploreStatus& status);
  // PROCMAN_STATUS of one deputy (wall-clock time, so it does not move t_s).
  void OnProcesses(const DeputyStatus& deputy);

  // The `update` frame for a page at `cursor`, or "" when nothing changed for it.
  std::string Update(ViewerCursor* cursor) const;

  // Message time of the newest input, seconds after the first.
  double t_s() const;
  // [t_s, known area m², mean edge D-optimality (NaN without edges)] once per second.
  const std::vector<std::array<double, 3>>& series() const { return series_; }
  const std::optional<FrontierList>& frontiers() const { return frontiers_; }

 private:
  void Advance(int64_t utime);
  // The map's changed tiles for a page ("" when the page's grid already equals it).
  std::string MapJson(ViewerCursor* cursor) const;

  std::optional<int64_t> first_utime_;
  int64_t latest_utime_ = 0;
  uint64_t version_ = 0;  // bumped by every change; each part keeps the version of its last

  std::optional<OccupancyGrid> map_;  // quantized as sent
  int64_t map_revision_ = 0;
  uint64_t map_version_ = 0;
  double known_area_m2_ = 0.0;

  std::optional<StampedPose> pose_;
  uint64_t pose_version_ = 0;
  // Poses after the newest keyframe, 5 cm apart (a page draws the keyframes, then these).
  std::vector<Point2d> trail_since_graph_m_;

  std::vector<Point2d> scan_m_;
  uint64_t scan_version_ = 0;

  std::vector<Point2d> nodes_m_;
  std::vector<std::array<int, 3>> edges_;  // from index, to index, kind
  uint64_t graph_version_ = 0;
  uint64_t graph_rewrite_version_ = 0;  // the last graph whose old nodes or edges changed
  double mean_edge_d_opt_ = 0.0;        // NaN without edges

  std::optional<FrontierList> frontiers_;
  std::vector<uint64_t> frontier_cells_hash_;  // per frontier of frontiers_
  uint64_t frontiers_version_ = 0;
  std::optional<ViewerScores> scores_;
  uint64_t scores_version_ = 0;
  std::optional<NavStatus> nav_;
  uint64_t nav_version_ = 0;
  std::vector<Point2d> path_m_;
  uint64_t path_version_ = 0;
  std::optional<ExploreStatus> explore_;
  uint64_t explore_version_ = 0;
  std::map<std::string, DeputyStatus> processes_;  // by deputy
  uint64_t processes_version_ = 0;

  std::vector<std::array<double, 3>> series_;
  int64_t next_series_utime_ = 0;
};

}  // namespace aslam
