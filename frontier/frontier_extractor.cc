#include "frontier/frontier_extractor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace aslam {
namespace {

// Guards ceil() against lengths that are whole multiples up to rounding (50 * 0.05 / 2.5).
constexpr double kRoundingSlack = 1e-9;

template <typename T>
[[noreturn]] void ThrowBadOption(const std::string& name, T value, const std::string& why) {
  std::ostringstream message;
  message << "FrontierOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

void CheckNonNegative(const std::string& name, double value) {
  if (!(value >= 0.0) || !std::isfinite(value))
    ThrowBadOption(name, value, "must be finite and >= 0");
}

bool IsKnownFree(int8_t value, int free_threshold) { return value >= 0 && value <= free_threshold; }

// Cuts one 8-connected cluster into pieces of equal arc length (see header, step 3).
// `origin` is the cluster's bounding box corner, `box_width`/`box_height` its size.
std::vector<std::vector<CellIndex>> SplitCluster(const std::vector<CellIndex>& cells,
                                                 CellIndex origin, int box_width, int box_height,
                                                 double resolution_m, double max_segment_length_m) {
  const int n = static_cast<int>(cells.size());
  std::vector<int> local(static_cast<std::size_t>(box_width) * box_height, -1);
  auto local_index = [&](int col, int row) -> int {
    const int c = col - origin.col;
    const int r = row - origin.row;
    if (c < 0 || r < 0 || c >= box_width || r >= box_height) return -1;
    return local[static_cast<std::size_t>(r) * box_width + c];
  };
  for (int i = 0; i < n; ++i) {
    local[static_cast<std::size_t>(cells[i].row - origin.row) * box_width + cells[i].col -
          origin.col] = i;
  }

  // Geodesic distances in cells from `source`, 8-connected inside the cluster.
  std::vector<double> distance(n);
  auto geodesic_from = [&](int source) {
    std::fill(distance.begin(), distance.end(), std::numeric_limits<double>::infinity());
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    distance[source] = 0.0;
    queue.push({0.0, source});
    while (!queue.empty()) {
      const auto [d, u] = queue.top();
      queue.pop();
      if (d > distance[u]) continue;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if (dr == 0 && dc == 0) continue;
          const int v = local_index(cells[u].col + dc, cells[u].row + dr);
          if (v < 0) continue;
          const double candidate = d + (dr != 0 && dc != 0 ? M_SQRT2 : 1.0);
          if (candidate < distance[v]) {
            distance[v] = candidate;
            queue.push({candidate, v});
          }
        }
      }
    }
    return static_cast<int>(std::max_element(distance.begin(), distance.end()) - distance.begin());
  };

  // Double sweep: the cell farthest from any cell is an end of the cluster.
  const int end = geodesic_from(0);
  const int far_end = geodesic_from(end);
  const double length_cells = distance[far_end] + 1.0;
  const int pieces =
      std::max(1, static_cast<int>(std::ceil(length_cells * resolution_m / max_segment_length_m -
                                             kRoundingSlack)));
  std::vector<std::vector<CellIndex>> segments(pieces);
  const double piece_cells = length_cells / pieces;
  for (int i = 0; i < n; ++i) {
    // Position of the cell's centre along the cluster, 0..length_cells.
    const int bin = std::min(pieces - 1, static_cast<int>((distance[i] + 0.5) / piece_cells));
    segments[bin].push_back(cells[i]);
  }
  segments.erase(std::remove_if(segments.begin(), segments.end(),
                                [](const std::vector<CellIndex>& s) { return s.empty(); }),
                 segments.end());
  return segments;
}

// FNV-1a over the cells' indices: a cluster's key in FrontierScratch::split_before.
uint64_t HashCells(const std::vector<CellIndex>& cells) {
  uint64_t hash = 1469598103934665603ull;
  for (const CellIndex& cell : cells) {
    for (const int v : {cell.col, cell.row}) {
      hash = (hash ^ static_cast<uint32_t>(v)) * 1099511628211ull;
    }
  }
  return hash;
}

// The segments `cells` were cut into last time, if it was a cluster then too.
const std::vector<std::vector<CellIndex>>* SplitBefore(
    const FrontierScratch::ClustersByHash& before, uint64_t hash,
    const std::vector<CellIndex>& cells) {
  const auto [first, last] = before.equal_range(hash);
  for (auto it = first; it != last; ++it) {
    if (it->second.cells == cells) return &it->second.segments;
  }
  return nullptr;
}

// True when every cell on the Bresenham line a..b (both included) is known free.
bool ClearLine(const OccupancyGrid& map, CellIndex a, CellIndex b, int free_threshold) {
  return VisitLine(a, b, [&](CellIndex cell) { return IsKnownFree(map.at(cell), free_threshold); });
}

// Offsets (col, row) of the square -reach..reach, nearest the centre first (by squared length).
std::vector<CellIndex> OffsetsNearestFirst(int reach) {
  std::vector<CellIndex> offsets;
  for (int row = -reach; row <= reach; ++row) {
    for (int col = -reach; col <= reach; ++col) offsets.push_back({col, row});
  }
  auto length2 = [](const CellIndex& o) { return o.col * o.col + o.row * o.row; };
  std::stable_sort(offsets.begin(), offsets.end(),
                   [&](const CellIndex& a, const CellIndex& b) { return length2(a) < length2(b); });
  return offsets;
}

// The reachable cell nearest the centroid that `accept` takes, among the segment's cells and
// the known-free cells within radius of the centroid that see the segment's cell nearest the
// centroid over known free space (so a target is never across a wall from its frontier);
// nullopt when there is none. Of equally near cells the segment's first wins, then the first
// in raster order.
template <typename Accept>
std::optional<CellIndex> NearestTarget(const OccupancyGrid& map, const ReachableCells& reachability,
                                       const std::vector<CellIndex>& segment, Point2d centroid_m,
                                       const FrontierOptions& options, const Accept& accept,
                                       std::vector<CellIndex>* offsets_nearest_first) {
  auto distance2 = [&](CellIndex cell) {
    const Point2d p = map.CellCenter(cell);
    return (p.x_m - centroid_m.x_m) * (p.x_m - centroid_m.x_m) +
           (p.y_m - centroid_m.y_m) * (p.y_m - centroid_m.y_m);
  };
  CellIndex anchor = segment.front();
  double anchor_d2 = distance2(anchor);
  std::optional<CellIndex> best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const CellIndex& cell : segment) {
    const double d2 = distance2(cell);
    if (d2 < anchor_d2) {
      anchor = cell;
      anchor_d2 = d2;
    }
    if (d2 < best_d2 && reachability.Reachable(cell) && accept(cell)) {
      best = cell;
      best_d2 = d2;
    }
  }

  // The window around the centroid's cell, nearest first: a cell at offset o lies at least
  // |o| * resolution - |centre - centroid| from the centroid, so the scan stops once that
  // bound passes the best distance found (or the radius).
  const double radius_m = options.target_radius_m;
  const double resolution_m = map.resolution_m();
  const CellIndex centre = map.WorldToCell(centroid_m);
  const int reach = static_cast<int>(std::ceil(radius_m / resolution_m)) + 1;
  const std::size_t side = 2 * static_cast<std::size_t>(reach) + 1;
  if (offsets_nearest_first->size() != side * side) {
    *offsets_nearest_first = OffsetsNearestFirst(reach);
  }
  const Point2d centre_m = map.CellCenter(centre);
  const double centre_offset_m =
      std::hypot(centre_m.x_m - centroid_m.x_m, centre_m.y_m - centroid_m.y_m) + 1e-9;
  bool best_in_window = false;
  for (const CellIndex& offset : *offsets_nearest_first) {
    const double lower_bound_m =
        std::sqrt(static_cast<double>(offset.col * offset.col + offset.row * offset.row)) *
            resolution_m -
        centre_offset_m;
    if (lower_bound_m > radius_m ||
        (lower_bound_m > 0.0 && lower_bound_m * lower_bound_m > best_d2)) {
      break;
    }
    const CellIndex cell{centre.col + offset.col, centre.row + offset.row};
    if (!map.Contains(cell)) continue;
    const double d2 = distance2(cell);
    const bool earlier_tie = d2 == best_d2 && best_in_window &&
                             std::tie(cell.row, cell.col) < std::tie(best->row, best->col);
    if (!(d2 < best_d2 || earlier_tie) || std::sqrt(d2) > radius_m) continue;
    if (!IsKnownFree(map.at(cell), options.free_threshold) || !reachability.Reachable(cell) ||
        !accept(cell) || !ClearLine(map, cell, anchor, options.free_threshold)) {
      continue;
    }
    best = cell;
    best_d2 = d2;
    best_in_window = true;
  }
  return best;
}

// Step 4's target: the nearest cell with room to stand (see the header), else the nearest.
// `room_offsets`: the offsets within the room's reach, nearest first (RoomOffsets).
std::optional<CellIndex> FindTarget(const OccupancyGrid& map, const ReachableCells& reachability,
                                    const std::vector<CellIndex>& segment, Point2d centroid_m,
                                    const FrontierOptions& options,
                                    const std::vector<CellIndex>& room_offsets,
                                    std::vector<CellIndex>* offsets_nearest_first) {
  if (!room_offsets.empty()) {
    auto has_room = [&](CellIndex cell) {
      for (const CellIndex& offset : room_offsets) {
        const CellIndex near{cell.col + offset.col, cell.row + offset.row};
        if (!map.Contains(near) || !IsKnownFree(map.at(near), options.free_threshold)) {
          return false;
        }
      }
      return true;
    };
    if (std::optional<CellIndex> roomy = NearestTarget(map, reachability, segment, centroid_m,
                                                       options, has_room, offsets_nearest_first)) {
      return roomy;
    }
  }
  return NearestTarget(
      map, reachability, segment, centroid_m, options, [](CellIndex) { return true; },
      offsets_nearest_first);
}

// The offsets o whose cell edge lies within room_m of a cell's centre (|o| * resolution -
// resolution / 2 < room_m), nearest first: a cell has room to stand when all of them are known
// free.
std::vector<CellIndex> RoomOffsets(double room_m, double resolution_m) {
  std::vector<CellIndex> offsets;
  const int reach = static_cast<int>(std::ceil(room_m / resolution_m)) + 1;
  for (const CellIndex& offset : OffsetsNearestFirst(reach)) {
    const double length_m =
        std::sqrt(static_cast<double>(offset.col * offset.col + offset.row * offset.row)) *
        resolution_m;
    if (length_m - 0.5 * resolution_m < room_m) offsets.push_back(offset);
  }
  return offsets;
}

}  // namespace

void ReachableCells::Compute(const Costmap& costmap, CellIndex start,
                             const GlobalPlannerOptions& options) {
  costmap_ = &costmap;
  use_tree_ = false;
  const int width = costmap.width_cells();
  const int height = costmap.height_cells();
  runs_.clear();
  row_first_run_.assign(static_cast<std::size_t>(height) + 1, 0);
  if (!costmap.Contains(start)) return;  // nothing is reachable from off the map
  if (!costmap.Traversable(start)) {
    GlobalPlanner(options).Search(costmap, start, {}, &tree_);
    use_tree_ = true;
    return;
  }
  // Each row's maximal runs of traversable cells.
  const uint8_t* costs = costmap.costs().data();
  for (int row = 0; row < height; ++row) {
    const uint8_t* line = costs + static_cast<std::size_t>(row) * width;
    int col = 0;
    while (col < width) {
      while (col < width && line[col] >= Costmap::kInscribed) ++col;
      if (col == width) break;
      const int begin = col;
      while (col < width && line[col] < Costmap::kInscribed) ++col;
      runs_.push_back({begin, col});
    }
    row_first_run_[row + 1] = static_cast<int>(runs_.size());
  }
  // 4-connected components: runs of adjacent rows that share a column are joined.
  run_parent_.resize(runs_.size());
  for (std::size_t i = 0; i < runs_.size(); ++i) run_parent_[i] = static_cast<int>(i);
  auto find = [this](int run) {
    while (run_parent_[run] != run) {
      run_parent_[run] = run_parent_[run_parent_[run]];  // path halving
      run = run_parent_[run];
    }
    return run;
  };
  for (int row = 1; row < height; ++row) {
    int above = row_first_run_[row - 1];
    int here = row_first_run_[row];
    const int above_end = row_first_run_[row];
    const int here_end = row_first_run_[row + 1];
    while (above < above_end && here < here_end) {
      const Run& a = runs_[above];
      const Run& b = runs_[here];
      if (a.col_begin < b.col_end && b.col_begin < a.col_end) {
        const int root_a = find(above), root_b = find(here);
        if (root_a != root_b) run_parent_[std::max(root_a, root_b)] = std::min(root_a, root_b);
      }
      if (a.col_end < b.col_end) {
        ++above;
      } else {
        ++here;
      }
    }
  }
  const int start_root = find(static_cast<int>(
      std::upper_bound(runs_.begin() + row_first_run_[start.row],
                       runs_.begin() + row_first_run_[start.row + 1], start.col,
                       [](int col, const Run& run) { return col < run.col_begin; }) -
      runs_.begin() - 1));
  run_reachable_.resize(runs_.size());
  std::size_t start_component_cells = 0;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    run_reachable_[i] = find(static_cast<int>(i)) == start_root;
    if (run_reachable_[i]) start_component_cells += runs_[i].col_end - runs_[i].col_begin;
  }
  // A start shut in a pocket leaves it as the planner does (its start escape), not by components.
  if (start_component_cells <= kStartPocketMaxCells) {
    GlobalPlanner(options).Search(costmap, start, {}, &tree_);
    use_tree_ = true;
  }
}

bool ReachableCells::Reachable(CellIndex cell) const {
  if (costmap_ == nullptr || !costmap_->Traversable(cell)) return false;
  if (use_tree_) return tree_.Reachable(cell);
  // A traversable cell lies in its row's last run that starts at or before it.
  const auto first = runs_.begin() + row_first_run_[cell.row];
  const auto last = runs_.begin() + row_first_run_[cell.row + 1];
  const auto after = std::upper_bound(first, last, cell.col,
                                      [](int col, const Run& run) { return col < run.col_begin; });
  return after != first && run_reachable_[after - runs_.begin() - 1] != 0;
}

void FrontierOptions::Validate() const {
  if (free_threshold < 0 || free_threshold >= costmap.occupied_threshold) {
    ThrowBadOption("free_threshold", free_threshold,
                   "must be in 0..costmap.occupied_threshold - 1 (" +
                       std::to_string(costmap.occupied_threshold - 1) + ")");
  }
  CheckNonNegative("min_size_m", min_size_m);
  if (!(max_segment_length_m > 0.0) || !std::isfinite(max_segment_length_m)) {
    ThrowBadOption("max_segment_length_m", max_segment_length_m, "must be finite and > 0");
  }
  CheckNonNegative("target_radius_m", target_radius_m);
  CheckNonNegative("target_clearance_m", target_clearance_m);
  CheckNonNegative("match_distance_m", match_distance_m);
  costmap.Validate();
  global_planner.Validate();
}

std::vector<Frontier> FindFrontiers(const OccupancyGrid& map, Point2d robot_m,
                                    const FrontierOptions& options, FrontierExtractionStats* stats,
                                    FrontierScratch* scratch) {
  FrontierExtractionStats local_stats;
  FrontierExtractionStats& s = stats ? *stats : local_stats;
  FrontierScratch local_scratch;
  FrontierScratch& m = scratch ? *scratch : local_scratch;
  s = FrontierExtractionStats{};
  std::vector<Frontier> frontiers;
  // Last extraction's split clusters serve only for the same cell size and segment length.
  m.split_now.clear();
  if (map.empty() || m.split_resolution_m != map.resolution_m() ||
      m.split_max_segment_length_m != options.max_segment_length_m) {
    m.split_before.clear();
  }
  m.split_resolution_m = map.resolution_m();
  m.split_max_segment_length_m = options.max_segment_length_m;
  if (map.empty()) return frontiers;

  const int width = map.width_cells();
  const int height = map.height_cells();
  const double resolution_m = map.resolution_m();

  // Step 1: known-free cells with an unknown 8-neighbour (off the map is not unknown), in
  // raster order. Byte loops without branches (the compiler vectorizes them): per row, the
  // unknown mask dilated along the row; a cell's 3 x 3 is that of the rows above, at, below.
  m.frontier.create(height, width, CV_8U);
  std::vector<CellIndex>& frontier_cells = m.frontier_cells;
  frontier_cells.clear();
  const std::vector<int8_t>& values = map.cells();
  std::vector<uint8_t>& padded = m.unknown_padded;  // one row's unknown mask, 0 either side
  padded.assign(static_cast<std::size_t>(width) + 2, 0);
  std::vector<uint8_t>& near = m.near_unknown_rows;  // rows -1 (zeros), 0..height-1, height
  near.resize(static_cast<std::size_t>(width) * (height + 2));
  // Only the two border rows need zeros: the loop below writes every other row.
  std::fill_n(near.begin(), width, 0);
  std::fill_n(near.end() - width, width, 0);
  // __restrict: byte pointers may alias anything, and a possible alias stops vectorizing.
  uint8_t* __restrict unknown = padded.data() + 1;
  for (int row = 0; row < height; ++row) {
    const int8_t* __restrict line = values.data() + static_cast<std::size_t>(row) * width;
    for (int col = 0; col < width; ++col) unknown[col] = line[col] == OccupancyGrid::kUnknown;
    uint8_t* __restrict dilated = near.data() + static_cast<std::size_t>(row + 1) * width;
    for (int col = 0; col < width; ++col) {
      dilated[col] = unknown[col - 1] | unknown[col] | unknown[col + 1];
    }
  }
  const int8_t free_threshold = static_cast<int8_t>(options.free_threshold);
  for (int row = 0; row < height; ++row) {
    const int8_t* __restrict line = values.data() + static_cast<std::size_t>(row) * width;
    const uint8_t* __restrict above = near.data() + static_cast<std::size_t>(row) * width;
    const uint8_t* __restrict at = above + width;
    const uint8_t* __restrict below = at + width;
    uint8_t* __restrict out = m.frontier.ptr<uint8_t>(row);
    for (int col = 0; col < width; ++col) {
      const uint8_t known_free = (line[col] >= 0) & (line[col] <= free_threshold);
      out[col] = known_free & (above[col] | at[col] | below[col]);
    }
    // Most rows hold few frontier cells: skip 8 zero bytes at a time.
    int col = 0;
    for (; col + 8 <= width; col += 8) {
      uint64_t eight;
      std::memcpy(&eight, out + col, sizeof(eight));
      if (eight == 0) continue;
      for (int c = col; c < col + 8; ++c) {
        if (out[c]) frontier_cells.push_back({c, row});
      }
    }
    for (; col < width; ++col) {
      if (out[col]) frontier_cells.push_back({col, row});
    }
  }
  s.frontier_cells = static_cast<int>(frontier_cells.size());
  if (s.frontier_cells == 0) {
    m.split_before.clear();
    return frontiers;
  }

  // Step 2: 8-connected clusters, each flood-filled from its first cell in
  // raster order, clearing its cells from the mask as it goes.
  const int min_cells =
      std::max(1, static_cast<int>(std::ceil(options.min_size_m / resolution_m - kRoundingSlack)));
  // Segments of each kept cluster, with the cluster's first 2 x 2 block (see the header).
  std::vector<std::pair<std::pair<int, int>, std::vector<std::vector<CellIndex>>>> clusters;
  std::vector<CellIndex>& cluster = m.cluster;
  for (const CellIndex& seed : frontier_cells) {
    const int seed_col = seed.col, seed_row = seed.row;
    if (!m.frontier.at<uint8_t>(seed_row, seed_col)) continue;  // in an earlier cluster
    ++s.clusters;
    cluster.clear();
    cluster.push_back({seed_col, seed_row});
    m.frontier.at<uint8_t>(seed_row, seed_col) = 0;
    CellIndex low = cluster.front(), high = cluster.front();  // bounding box corners
    std::pair<int, int> first_block{seed_row / 2, seed_col / 2};
    for (std::size_t head = 0; head < cluster.size(); ++head) {
      const CellIndex u = cluster[head];
      for (int row = std::max(0, u.row - 1); row <= std::min(height - 1, u.row + 1); ++row) {
        uint8_t* line = m.frontier.ptr<uint8_t>(row);
        for (int col = std::max(0, u.col - 1); col <= std::min(width - 1, u.col + 1); ++col) {
          if (!line[col]) continue;
          line[col] = 0;
          cluster.push_back({col, row});
          low = {std::min(low.col, col), std::min(low.row, row)};
          high = {std::max(high.col, col), std::max(high.row, row)};
          first_block = std::min(first_block, std::make_pair(row / 2, col / 2));
        }
      }
    }
    if (static_cast<int>(cluster.size()) < min_cells) {
      ++s.clusters_too_small;
      continue;
    }
    // Step 3: segments of bounded length, from the cluster's cells in raster order.
    std::sort(cluster.begin(), cluster.end(), [](const CellIndex& a, const CellIndex& b) {
      return a.row != b.row ? a.row < b.row : a.col < b.col;
    });
    const uint64_t hash = HashCells(cluster);
    FrontierScratch::ClusterSegments split{cluster, {}};
    if (const auto* before = SplitBefore(m.split_before, hash, cluster)) {
      split.segments = *before;
    } else {
      ++s.clusters_split;
      split.segments = SplitCluster(cluster, low, high.col - low.col + 1, high.row - low.row + 1,
                                    resolution_m, options.max_segment_length_m);
    }
    clusters.emplace_back(first_block, split.segments);
    m.split_now.emplace(hash, std::move(split));
  }
  std::swap(m.split_before, m.split_now);
  // Clusters in the order of their first 2 x 2 block (blocks in raster order); no two
  // clusters share a block, as a block's cells are all 8-neighbours.
  std::sort(clusters.begin(), clusters.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::vector<CellIndex>> segments;
  for (auto& [block, pieces] : clusters) {
    for (auto& segment : pieces) segments.push_back(std::move(segment));
  }
  s.segments = static_cast<int>(segments.size());
  if (segments.empty()) return frontiers;

  // Step 4: targets in the navigator's costmap, reachable from the robot.
  m.costmap.Update(map, options.costmap);
  m.reachable.Compute(m.costmap, map.WorldToCell(robot_m), options.global_planner);
  const ReachableCells& reachability = m.reachable;
  s.used_planner_search = reachability.used_planner_search();
  const double room_m = options.target_clearance_m > 0.0
                            ? options.costmap.robot_radius_m + options.costmap.clearance_margin_m +
                                  options.target_clearance_m
                            : 0.0;
  if (room_m != m.room_m || map.resolution_m() != m.room_resolution_m) {
    m.room_m = room_m;
    m.room_resolution_m = map.resolution_m();
    m.room_offsets.clear();
    if (room_m > 0.0) m.room_offsets = RoomOffsets(room_m, map.resolution_m());
  }
  for (std::vector<CellIndex>& segment : segments) {
    Frontier frontier;
    frontier.id = -1;
    frontier.points_m.reserve(segment.size());
    double sum_x = 0.0, sum_y = 0.0;
    for (const CellIndex& cell : segment) {
      const Point2d p = map.CellCenter(cell);
      frontier.points_m.push_back(p);
      sum_x += p.x_m;
      sum_y += p.y_m;
    }
    const double n = static_cast<double>(segment.size());
    frontier.centroid_m = {sum_x / n, sum_y / n};
    const std::optional<CellIndex> target =
        FindTarget(map, reachability, segment, frontier.centroid_m, options, m.room_offsets,
                   &m.target_offsets);
    if (!target) {
      ++s.segments_unreachable;
      continue;
    }
    frontier.target_m = map.CellCenter(*target);
    frontier.cells = std::move(segment);
    frontiers.push_back(std::move(frontier));
  }
  return frontiers;
}

void AssignFrontierIds(const std::vector<Frontier>& previous, double match_distance_m,
                       std::vector<Frontier>* frontiers, int* next_id) {
  std::vector<Frontier>& current = *frontiers;
  // Every close pair, closest first (ties by index: deterministic); squared distances order
  // the pairs as distances do.
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  const double match_distance2 = match_distance_m * match_distance_m;
  for (std::size_t i = 0; i < current.size(); ++i) {
    for (std::size_t j = 0; j < previous.size(); ++j) {
      const double dx = current[i].centroid_m.x_m - previous[j].centroid_m.x_m;
      const double dy = current[i].centroid_m.y_m - previous[j].centroid_m.y_m;
      const double d2 = dx * dx + dy * dy;
      if (d2 <= match_distance2) pairs.emplace_back(d2, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> current_taken(current.size(), false);
  std::vector<bool> previous_taken(previous.size(), false);
  for (const auto& [d2, i, j] : pairs) {
    if (current_taken[i] || previous_taken[j]) continue;
    current_taken[i] = previous_taken[j] = true;
    current[i].id = previous[j].id;
  }
  for (std::size_t i = 0; i < current.size(); ++i) {
    if (!current_taken[i]) current[i].id = (*next_id)++;
  }
  std::sort(current.begin(), current.end(),
            [](const Frontier& a, const Frontier& b) { return a.id < b.id; });
}

FrontierExtractor::FrontierExtractor(FrontierOptions options) : options_(std::move(options)) {
  options_.Validate();
}

const std::vector<Frontier>& FrontierExtractor::Extract(const OccupancyGrid& map, Point2d robot_m) {
  std::vector<Frontier> found = FindFrontiers(map, robot_m, options_, &stats_, &scratch_);
  AssignFrontierIds(frontiers_, options_.match_distance_m, &found, &next_id_);
  frontiers_ = std::move(found);
  return frontiers_;
}

}  // namespace aslam
