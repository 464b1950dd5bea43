#include "viewer/viewer_model.h"

#include <glib.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "common/json_text.h"
#include "common/text_format.h"
#include "eval/graph_metrics.h"

namespace aslam {
namespace {

constexpr uint8_t kUnknownByte = 255;
constexpr double kTrailSpacingM = 0.05;
constexpr std::size_t kMaxScanPoints = 360;  // a picture of the scan, not the scan
constexpr int64_t kSeriesPeriodUs = 1'000'000;

// A number for a page: fixed decimals (metres to the millimetre is plenty), null if not finite.
std::string Num(double value, int decimals = 3) {
  if (!std::isfinite(value)) return "null";
  return Format("%.*f", decimals, value);
}

// Drawn points to the centimetre: a page shows 5 cm cells.
std::string PointJson(Point2d p) { return "[" + Num(p.x_m, 2) + "," + Num(p.y_m, 2) + "]"; }

std::string PointsJson(const std::vector<Point2d>& points, std::size_t from = 0) {
  std::string out = "[";
  for (std::size_t i = from; i < points.size(); ++i) {
    if (i > from) out += ",";
    out += PointJson(points[i]);
  }
  return out + "]";
}

// Occupancy in steps of 10 %: a page shows shades, and small changes then send nothing.
int8_t Quantize(int8_t value) {
  if (value < 0) return OccupancyGrid::kUnknown;
  return static_cast<int8_t>(std::min(100, (value + 5) / 10 * 10));
}

bool SameGeometry(const OccupancyGrid& a, const OccupancyGrid& b) {
  return a.width_cells() == b.width_cells() && a.height_cells() == b.height_cells() &&
         a.resolution_m() == b.resolution_m() && a.origin_m().x_m == b.origin_m().x_m &&
         a.origin_m().y_m == b.origin_m().y_m;
}

// The whole cells by which `to`'s origin lies below and left of `from`'s, if the two grids
// share their resolution and their cell lattice.
std::optional<CellIndex> LatticeOffset(const OccupancyGrid& from, const OccupancyGrid& to) {
  if (from.resolution_m() != to.resolution_m()) return std::nullopt;
  const double dx = (from.origin_m().x_m - to.origin_m().x_m) / to.resolution_m();
  const double dy = (from.origin_m().y_m - to.origin_m().y_m) / to.resolution_m();
  const double cx = std::round(dx);
  const double cy = std::round(dy);
  if (std::abs(dx - cx) > 1e-3 || std::abs(dy - cy) > 1e-3) return std::nullopt;
  return CellIndex{static_cast<int>(cx), static_cast<int>(cy)};
}

// What a page does with a `full: false` map of new geometry: the old cells at their place.
OccupancyGrid Regrid(const OccupancyGrid& old, const OccupancyGrid& geometry, CellIndex offset) {
  OccupancyGrid out(geometry.width_cells(), geometry.height_cells(), geometry.resolution_m(),
                    geometry.origin_m());
  for (int row = 0; row < old.height_cells(); ++row) {
    const int to_row = row + offset.row;
    if (to_row < 0 || to_row >= out.height_cells()) continue;
    for (int col = 0; col < old.width_cells(); ++col) {
      const int to_col = col + offset.col;
      if (to_col < 0 || to_col >= out.width_cells()) continue;
      out.at({to_col, to_row}) = old.at({col, row});
    }
  }
  return out;
}

bool TileDiffers(const OccupancyGrid& a, const OccupancyGrid& b, int x, int y, int w, int h) {
  for (int row = y; row < y + h; ++row) {
    const std::size_t start = a.LinearIndex({x, row});
    if (std::memcmp(a.cells().data() + start, b.cells().data() + start, w) != 0) return true;
  }
  return false;
}

// {"x":..,"cells":"<base64 of zlib>"} for one tile.
std::string TileJson(const OccupancyGrid& grid, int x, int y, int w, int h) {
  std::vector<uint8_t> bytes;
  bytes.reserve(static_cast<std::size_t>(w) * h);
  for (int row = y; row < y + h; ++row) {
    for (int col = x; col < x + w; ++col) {
      const int8_t v = grid.at({col, row});
      bytes.push_back(v < 0 ? kUnknownByte : static_cast<uint8_t>(v));
    }
  }
  uLongf size = compressBound(bytes.size());
  std::vector<uint8_t> z(size);
  if (compress2(z.data(), &size, bytes.data(), bytes.size(), Z_DEFAULT_COMPRESSION) != Z_OK) {
    throw std::runtime_error("zlib could not compress a map tile");
  }
  gchar* base64 = g_base64_encode(z.data(), size);
  std::string out =
      Format("{\"x\":%d,\"y\":%d,\"w\":%d,\"h\":%d,\"cells\":\"%s\"}", x, y, w, h, base64);
  g_free(base64);
  return out;
}

std::string ScoresJson(const ViewerScores& s) {
  std::string rows;
  for (const FrontierScore& r : s.scores) {
    if (!rows.empty()) rows += ",";
    rows += JsonObject({{"frontier_id", std::to_string(r.frontier_id)},
                        {"target", PointJson(r.target_m)},
                        {"path_length_m", Num(r.path_length_m, 2)},
                        {"u1", Num(r.u1, 4)},
                        {"mean_entropy_bits", Num(r.mean_entropy_bits, 4)},
                        {"ray_cells", std::to_string(r.ray_cells)},
                        {"gamma", Num(r.gamma, 4)},
                        {"rho", Num(r.rho, 4)},
                        {"u2", Num(r.u2, 4)},
                        {"total", Num(r.total, 4)},
                        {"eligible", r.eligible() ? "true" : "false"},
                        {"reason", JsonString(r.eligible() ? "" : EligibilityName(r.eligibility))},
                        {"chosen", r.chosen ? "true" : "false"}});
  }
  return JsonObject({{"decision_id", std::to_string(s.decision_id)},
                     {"method", JsonString(s.method)},
                     {"chosen_frontier_id", std::to_string(s.chosen_frontier_id)},
                     {"rows", "[" + rows + "]"}});
}

// FNV-1a over the cells' coordinates as drawn (to the centimetre).
uint64_t CellsHash(const std::vector<Point2d>& points) {
  uint64_t hash = 1469598103934665603ull;
  for (const Point2d& p : points) {
    for (const double v : {p.x_m, p.y_m}) {
      hash ^= static_cast<uint64_t>(std::llround(v * 100.0));
      hash *= 1099511628211ull;
    }
  }
  return hash;
}

// Every frontier; the cells only of those whose cells the page does not have yet (a frontier
// without "cells" keeps those of its id), the bulk of the traffic otherwise.
std::string FrontiersJson(const FrontierList& list, const std::vector<uint64_t>& hashes,
                          std::map<int, uint64_t>* sent) {
  std::map<int, uint64_t> now;
  std::string out = "[";
  for (std::size_t i = 0; i < list.frontiers.size(); ++i) {
    const Frontier& f = list.frontiers[i];
    std::vector<std::pair<std::string, std::string>> fields = {
        {"id", std::to_string(f.id)},
        {"centroid", PointJson(f.centroid_m)},
        {"target", PointJson(f.target_m)},
        {"size", std::to_string(f.size_cells())}};
    const auto known = sent->find(f.id);
    if (known == sent->end() || known->second != hashes[i]) {
      fields.push_back({"cells", PointsJson(f.points_m)});
    }
    now[f.id] = hashes[i];
    out += (i ? "," : "") + JsonObject(fields);
  }
  *sent = std::move(now);
  return out + "]";
}

std::string SeriesPointJson(const std::array<double, 3>& p) {
  return "[" + Num(p[0], 1) + "," + Num(p[1], 2) + "," + Num(p[2], 2) + "]";
}

}  // namespace

void ViewerModel::Advance(int64_t utime) {
  if (!first_utime_) {
    first_utime_ = utime;
    next_series_utime_ = utime;
  }
  latest_utime_ = std::max(latest_utime_, utime);
  // One sample per second of message time, of the newest values.
  while (latest_utime_ >= next_series_utime_) {
    series_.push_back({(next_series_utime_ - *first_utime_) * 1e-6, known_area_m2_,
                       edges_.empty() ? std::nan("") : mean_edge_d_opt_});
    next_series_utime_ += kSeriesPeriodUs;
  }
  ++version_;
}

double ViewerModel::t_s() const {
  return first_utime_ ? (latest_utime_ - *first_utime_) * 1e-6 : 0.0;
}

void ViewerModel::OnMap(const OccupancyGrid& grid, int64_t revision, int64_t utime) {
  OccupancyGrid quantized = grid;
  int64_t known = 0;
  for (int8_t& v : quantized.mutable_cells()) {
    v = Quantize(v);
    if (v >= 0) ++known;
  }
  known_area_m2_ = known * grid.resolution_m() * grid.resolution_m();
  map_ = std::move(quantized);
  map_revision_ = revision;
  Advance(utime);
  map_version_ = version_;
}

void ViewerModel::OnPose(const StampedPose& pose) {
  pose_ = pose;
  const Point2d p{pose.pose.x_m, pose.pose.y_m};
  if (trail_since_graph_m_.empty() ||
      std::hypot(p.x_m - trail_since_graph_m_.back().x_m,
                 p.y_m - trail_since_graph_m_.back().y_m) >= kTrailSpacingM) {
    trail_since_graph_m_.push_back(p);
  }
  Advance(pose.utime);
  pose_version_ = version_;
}

void ViewerModel::OnScan(const LidarScan& scan) {
  if (!pose_) return;  // nowhere to place it yet
  const Pose2d sensor = pose_->pose * scan.sensor_pose;
  const std::size_t step = std::max<std::size_t>(1, scan.range_m.size() / kMaxScanPoints);
  scan_m_.clear();
  for (std::size_t i = 0; i < scan.range_m.size(); i += step) {
    if (!scan.IsValidReturn(i)) continue;
    const double angle = scan.BeamAngle(i);
    const double r = scan.range_m[i];
    scan_m_.push_back(sensor.Transform({r * std::cos(angle), r * std::sin(angle)}));
  }
  Advance(scan.utime);
  scan_version_ = version_;
}

void ViewerModel::OnGraph(const PoseGraph& graph, int64_t utime) {
  // Node ids are dense from 0 (a POSE_GRAPH is rejected otherwise), so an id is its index.
  std::vector<Point2d> nodes;
  for (const PoseGraphNode& node : graph.nodes) nodes.push_back({node.pose.x_m, node.pose.y_m});
  std::vector<std::array<int, 3>> edges;
  for (const PoseGraphEdge& edge : graph.edges) {
    edges.push_back({edge.from_id, edge.to_id, edge.kind == EdgeKind::kLoopClosure ? 1 : 0});
  }
  // Pages get only the new keyframes and edges unless the old ones moved (a loop closure)
  // by a centimetre (what they are drawn to) or the graph shrank (a SLAM restart).
  bool rewritten = nodes.size() < nodes_m_.size() || edges.size() < edges_.size() ||
                   !std::equal(edges_.begin(), edges_.end(), edges.begin());
  for (std::size_t i = 0; i < nodes_m_.size() && !rewritten; ++i) {
    rewritten = std::hypot(nodes[i].x_m - nodes_m_[i].x_m, nodes[i].y_m - nodes_m_[i].y_m) >= 0.01;
  }
  nodes_m_ = std::move(nodes);
  edges_ = std::move(edges);
  mean_edge_d_opt_ = graph.edges.empty() ? std::nan("") : MeanEdgeDOptimality(graph);
  // The trail is the keyframes (optimized) plus the poses after the newest of them.
  if (!trail_since_graph_m_.empty()) {
    trail_since_graph_m_.erase(trail_since_graph_m_.begin(), trail_since_graph_m_.end() - 1);
  }
  Advance(utime);
  graph_version_ = version_;
  if (rewritten) graph_rewrite_version_ = version_;
}

void ViewerModel::OnFrontiers(const FrontierList& frontiers) {
  frontiers_ = frontiers;
  frontier_cells_hash_.clear();
  for (const Frontier& f : frontiers.frontiers)
    frontier_cells_hash_.push_back(CellsHash(f.points_m));
  Advance(frontiers.utime);
  frontiers_version_ = version_;
}

void ViewerModel::OnScores(ViewerScores scores, int64_t utime) {
  scores_ = std::move(scores);
  Advance(utime);
  scores_version_ = version_;
}

void ViewerModel::OnNavStatus(const NavStatus& nav) {
  // At 10 Hz the distance creeps; a page needs it to 5 cm.
  const bool changed = !nav_ || nav_->state != nav.state || nav_->goal_id != nav.goal_id ||
                       nav_->detail != nav.detail || nav_->recovery != nav.recovery ||
                       std::abs(nav_->distance_remaining_m - nav.distance_remaining_m) >= 0.05;
  nav_ = nav;
  Advance(nav.utime);
  if (changed) nav_version_ = version_;
}

void ViewerModel::OnNavPath(std::vector<Point2d> path_m, int64_t utime) {
  path_m_ = std::move(path_m);
  Advance(utime);
  path_version_ = version_;
}

void ViewerModel::OnExploreStatus(const ExploreStatus& status) {
  explore_ = status;
  Advance(status.utime);
  explore_version_ = version_;
}

void ViewerModel::OnProcesses(const DeputyStatus& deputy) {
  processes_[deputy.deputy] = deputy;
  processes_version_ = ++version_;
}

std::string ViewerModel::MapJson(ViewerCursor* cursor) const {
  const OccupancyGrid& grid = *map_;
  bool full = !cursor->map;
  const bool geometry_changed = cursor->map && !SameGeometry(*cursor->map, grid);
  if (geometry_changed) {
    const std::optional<CellIndex> offset = LatticeOffset(*cursor->map, grid);
    if (offset) {
      cursor->map = Regrid(*cursor->map, grid, *offset);
    } else {
      full = true;
    }
  }
  if (full)
    cursor->map = OccupancyGrid(grid.width_cells(), grid.height_cells(), grid.resolution_m(),
                                grid.origin_m());
  std::string tiles;
  for (int y = 0; y < grid.height_cells(); y += kTileCells) {
    const int h = std::min(kTileCells, grid.height_cells() - y);
    for (int x = 0; x < grid.width_cells(); x += kTileCells) {
      const int w = std::min(kTileCells, grid.width_cells() - x);
      if (!TileDiffers(grid, *cursor->map, x, y, w, h)) continue;
      if (!tiles.empty()) tiles += ",";
      tiles += TileJson(grid, x, y, w, h);
    }
  }
  cursor->map = grid;
  cursor->map_version = map_version_;
  if (!full && tiles.empty() && !geometry_changed) return "";  // a re-announce: nothing new
  return Format(
      "{\"revision\":%lld,\"width\":%d,\"height\":%d,\"resolution_m\":%s,"
      "\"origin\":{\"x_m\":%s,\"y_m\":%s,\"yaw_rad\":0},\"full\":%s,\"tiles\":[%s]}",
      static_cast<long long>(map_revision_), grid.width_cells(), grid.height_cells(),
      Num(grid.resolution_m(), 4).c_str(), Num(grid.origin_m().x_m, 4).c_str(),
      Num(grid.origin_m().y_m, 4).c_str(), full ? "true" : "false", tiles.c_str());
}

std::string ViewerModel::Update(ViewerCursor* cursor) const {
  std::vector<std::pair<std::string, std::string>> fields;
  const bool reset = cursor->reset_pending;
  if (reset) {
    *cursor = ViewerCursor{};
    cursor->reset_pending = false;
    fields.push_back({"reset", "true"});
  }
  if (map_ && cursor->map_version != map_version_) {
    const std::string map = MapJson(cursor);
    if (!map.empty()) fields.push_back({"map", map});
  }
  if (pose_ && cursor->pose_version != pose_version_) {
    fields.push_back(
        {"pose", Format("{\"x_m\":%s,\"y_m\":%s,\"yaw_rad\":%s}", Num(pose_->pose.x_m).c_str(),
                        Num(pose_->pose.y_m).c_str(), Num(pose_->pose.yaw_rad).c_str())});
    cursor->pose_version = pose_version_;
  }
  if (cursor->graph_version != graph_version_ || reset) {
    const bool whole = reset || cursor->graph_rewrite_version != graph_rewrite_version_;
    const std::size_t from_node = whole ? 0 : cursor->graph_nodes_sent;
    const std::size_t from_edge = whole ? 0 : cursor->graph_edges_sent;
    std::string edges = "[";
    for (std::size_t i = from_edge; i < edges_.size(); ++i) {
      edges += Format("%s[%d,%d,%d]", i > from_edge ? "," : "", edges_[i][0], edges_[i][1],
                      edges_[i][2]);
    }
    fields.push_back(
        {whole ? "graph" : "graph_append",
         "{\"nodes\":" + PointsJson(nodes_m_, from_node) + ",\"edges\":" + edges + "]}"});
    fields.push_back({"trail", PointsJson(trail_since_graph_m_)});
    cursor->graph_version = graph_version_;
    cursor->graph_rewrite_version = graph_rewrite_version_;
    cursor->graph_nodes_sent = nodes_m_.size();
    cursor->graph_edges_sent = edges_.size();
    cursor->trail_sent = trail_since_graph_m_.size();
  } else if (cursor->trail_sent < trail_since_graph_m_.size()) {
    fields.push_back({"trail_append", PointsJson(trail_since_graph_m_, cursor->trail_sent)});
    cursor->trail_sent = trail_since_graph_m_.size();
  }
  if (!scan_m_.empty() && cursor->scan_version != scan_version_) {
    fields.push_back({"scan", PointsJson(scan_m_)});
    cursor->scan_version = scan_version_;
  }
  if (frontiers_ && cursor->frontiers_version != frontiers_version_) {
    fields.push_back({"frontiers", FrontiersJson(*frontiers_, frontier_cells_hash_,
                                                 &cursor->frontier_cells_sent)});
    cursor->frontiers_version = frontiers_version_;
  }
  if (scores_ && cursor->scores_version != scores_version_) {
    fields.push_back({"scores", ScoresJson(*scores_)});
    cursor->scores_version = scores_version_;
  }
  // The state when it changed, the path (newest NAV_PATH) only when that changed.
  std::vector<std::pair<std::string, std::string>> nav;
  if (nav_ && cursor->nav_version != nav_version_) {
    // "active (rotate)" while a recovery runs.
    const std::string state = std::string(NavStateName(nav_->state)) +
                              (nav_->recovery == RecoveryPhase::kNone
                                   ? ""
                                   : std::string(" (") + RecoveryPhaseName(nav_->recovery) + ")");
    nav = {{"state", JsonString(state)},
           {"goal_id", std::to_string(nav_->goal_id)},
           {"goal", PointJson(nav_->goal_m)},
           {"distance_remaining_m", Num(nav_->distance_remaining_m, 2)},
           {"detail", JsonString(nav_->detail)}};
    cursor->nav_version = nav_version_;
  }
  if (cursor->path_version != path_version_) {
    nav.push_back({"path", PointsJson(path_m_)});
    cursor->path_version = path_version_;
  }
  if (!nav.empty()) fields.push_back({"nav", JsonObject(nav)});
  if (explore_ && cursor->explore_version != explore_version_) {
    const ExploreStatus& e = *explore_;
    fields.push_back({"explore", JsonObject({{"state", JsonString(ExploreStateName(e.state))},
                                             {"detail", JsonString(e.detail)},
                                             {"method", JsonString(UtilityMethodName(e.method))},
                                             {"current_goal_id", std::to_string(e.current_goal_id)},
                                             {"num_frontiers", std::to_string(e.num_frontiers)},
                                             {"num_eligible", std::to_string(e.num_eligible)},
                                             {"decisions", std::to_string(e.decisions)},
                                             {"goals_reached", std::to_string(e.goals_reached)},
                                             {"goals_failed", std::to_string(e.goals_failed)}})});
    cursor->explore_version = explore_version_;
  }
  if (cursor->series_sent < series_.size()) {
    std::string points = "[";
    for (std::size_t i = cursor->series_sent; i < series_.size(); ++i) {
      points += (i > cursor->series_sent ? "," : "") + SeriesPointJson(series_[i]);
    }
    fields.push_back({reset ? "series" : "series_append", points + "]"});
    cursor->series_sent = series_.size();
  }
  if (!processes_.empty() && cursor->processes_version != processes_version_) {
    std::string list = "[";
    for (const auto& [deputy, status] : processes_) {
      for (const ProcessStatus& p : status.processes) {
        if (list.size() > 1) list += ",";
        list += JsonObject({{"name", JsonString(p.name)},
                            {"host", JsonString(deputy)},
                            {"state", JsonString(ProcessStateName(p.state))},
                            {"pid", std::to_string(p.pid)},
                            {"restarts", std::to_string(p.restarts)},
                            {"cpu_percent", Num(p.cpu_percent, 1)},
                            {"rss_mb", Num(p.rss_bytes / 1e6, 1)},
                            {"last_exit", std::to_string(p.exit_code)}});
      }
    }
    fields.push_back({"processes", list + "]"});
    cursor->processes_version = processes_version_;
  }
  if (fields.empty()) return "";
  fields.insert(fields.begin(), {{"type", "\"update\""}, {"t_s", Num(t_s(), 2)}});
  return JsonObject(fields);
}

}  // namespace aslam
