#include "utility/hallucination.h"

// Interpretations of docs/architecture.md §5 made here (one decision each):
// - path_cells = path_m.size(); the path runs robot (index 0) → frontier target
//   (index path_cells − 1).
// - K = ceil(path_cells / path_cells_per_node) nodes split the path into K + 1
//   equal stretches: node k (1..K) at index round(k·(path_cells−1)/(K+1)), and
//   node K+1 at the frontier (index path_cells − 1). None at the robot: the
//   newest graph node stands for it.
// - Heading of a node: direction of the path through it (from the previous to
//   the next path point, one-sided at the ends); the newest node's yaw for a
//   one-cell path.
// - New node k (0-based) is node N + k of the extended graph, N = graph size.
//   The chain is newest (N−1) → N → N+1 → ...; the edge into node N+k gets
//   I_odo·(1 + u) with u of node N+k.
// - "Within r of a node": grid cells whose centre lies within r of the node's
//   position. Cells off the grid count as unknown (not yet mapped) and are in
//   the denominator of both fractions.
// - "Occupied": map value >= 65 — our SLAM renderer maps p >= 0.65 to 100 and
//   values in 1..64 are uncertain, so this equals "== 100" with our renderer
//   and matches ROS's 0.65 occupied threshold for other maps.
// - Loop closures: from new node i = N+k to the base nodes j < N − 20 (the 20
//   newest base nodes excluded) within 2.0 m of it (by the graph's pose
//   estimates), the nearest 5 (ties by lower index), only when node i's
//   occupied fraction > 0.03; I = I_odo·1.5·(|i−j|/N)·occupied fraction with
//   N the base graph's size. New nodes never close loops among themselves.

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/LU>

namespace aslam {
namespace {

constexpr int8_t kOccupiedValue = 65;
// Cells exactly on the circle are inside; the slack keeps rounding from flipping them.
constexpr double kOnCircleTolerance_m2 = 1e-9;

struct CellFractions {
  double unknown = 0.0;
  double occupied = 0.0;
};

CellFractions FractionsWithin(const OccupancyGrid& map, Point2d center_m, double radius_m) {
  if (map.empty()) return {1.0, 0.0};  // nothing mapped yet
  const double resolution_m = map.resolution_m();
  const Point2d origin = map.origin_m();
  const double reach_sq = radius_m * radius_m + kOnCircleTolerance_m2;
  // Cell (col, row) has its centre at origin + (index + 0.5)·resolution; walk
  // the rows of the disc and count each row's span of columns.
  const double center_col = (center_m.x_m - origin.x_m) / resolution_m - 0.5;
  const double center_row = (center_m.y_m - origin.y_m) / resolution_m - 0.5;
  const int row_lo = static_cast<int>(std::ceil(center_row - radius_m / resolution_m - 1.0));
  const int row_hi = static_cast<int>(std::floor(center_row + radius_m / resolution_m + 1.0));
  long total = 0, unknown = 0, occupied = 0;
  const std::vector<int8_t>& cells = map.cells();
  for (int row = row_lo; row <= row_hi; ++row) {
    const double dy_m = origin.y_m + (row + 0.5) * resolution_m - center_m.y_m;
    const double rest_sq = reach_sq - dy_m * dy_m;
    if (rest_sq < 0.0) continue;
    const double half_width_cells = std::sqrt(rest_sq) / resolution_m;
    const int col_lo = static_cast<int>(std::ceil(center_col - half_width_cells));
    const int col_hi = static_cast<int>(std::floor(center_col + half_width_cells));
    if (col_hi < col_lo) continue;
    const int span = col_hi - col_lo + 1;
    total += span;
    if (row < 0 || row >= map.height_cells()) {  // the whole span is off the grid
      unknown += span;
      continue;
    }
    const int in_lo = std::max(col_lo, 0);
    const int in_hi = std::min(col_hi, map.width_cells() - 1);
    unknown += span - std::max(0, in_hi - in_lo + 1);  // off-grid columns
    // Branch-free counts (the compiler vectorizes them): a disc is ~1300 cells per node.
    const int8_t* row_cells = cells.data() + static_cast<std::size_t>(row) * map.width_cells();
    int row_unknown = 0, row_occupied = 0;
    for (int col = in_lo; col <= in_hi; ++col) {
      const int8_t value = row_cells[col];
      row_unknown += value < 0;
      row_occupied += value >= kOccupiedValue;
    }
    unknown += row_unknown;
    occupied += row_occupied;
  }
  if (total == 0) return {1.0, 0.0};  // radius below half a cell and off-centre: treat as unmapped
  return {static_cast<double>(unknown) / total, static_cast<double>(occupied) / total};
}

double HeadingAt(const std::vector<Point2d>& path_m, int index, double fallback_rad) {
  const int last = static_cast<int>(path_m.size()) - 1;
  const Point2d& a = path_m[std::max(index - 1, 0)];
  const Point2d& b = path_m[std::min(index + 1, last)];
  const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
  if (dx == 0.0 && dy == 0.0) return fallback_rad;
  return std::atan2(dy, dx);
}

std::string Describe(const char* field, double value) {
  std::ostringstream out;
  out << "HallucinationOptions." << field << " = " << value << " is invalid";
  return out.str();
}

}  // namespace

Eigen::Matrix3d OdometryInformation(const HallucinationOptions& options) {
  Eigen::Matrix3d sigma;
  sigma << options.odometry_sigma_xx, options.odometry_sigma_xy, 0.0,  //
      options.odometry_sigma_xy, options.odometry_sigma_yy, 0.0,       //
      0.0, 0.0, options.odometry_sigma_yawyaw;
  return 0.5 * sigma.inverse();  // I_odo = ½·inv(Σ_odo), docs/architecture.md §5
}

Hallucination HallucinatePathDetailed(const PoseGraph& graph, const std::vector<Point2d>& path_m,
                                      const OccupancyGrid& map,
                                      const HallucinationOptions& options) {
  Hallucination result;
  const int num_base = static_cast<int>(graph.nodes.size());
  const int path_cells = static_cast<int>(path_m.size());
  if (num_base == 0 || path_cells == 0) return result;

  const Pose2d newest = graph.nodes.back().pose;
  const int num_interior =
      (path_cells + options.path_cells_per_node - 1) / options.path_cells_per_node;
  const int num_new = num_interior + 1;
  for (int k = 1; k <= num_new; ++k) {
    HallucinatedNode node;
    node.path_index =
        k == num_new
            ? path_cells - 1
            : static_cast<int>(std::lround(static_cast<double>(k) * (path_cells - 1) / num_new));
    const Point2d& at = path_m[node.path_index];
    node.pose = {at.x_m, at.y_m, HeadingAt(path_m, node.path_index, newest.yaw_rad)};
    const CellFractions fractions = FractionsWithin(map, at, options.unknown_radius_m);
    node.unknown_fraction = fractions.unknown;
    node.occupied_fraction = fractions.occupied;
    result.nodes.push_back(node);
  }

  const Eigen::Matrix3d odometry_information = OdometryInformation(options);
  const int last_eligible =
      num_base - options.exclude_newest_nodes;  // base nodes j < this may close loops
  const double radius_sq = options.loop_closure_radius_m * options.loop_closure_radius_m;
  // Base nodes that may close a loop with any new node: eligible index, inside
  // the new nodes' bounding box grown by the radius (one pass over the graph),
  // binned on a grid of cells a bit wider than the radius so that each new node
  // looks at the 3x3 bins around it only (a long path's box holds most of the graph).
  const double r = options.loop_closure_radius_m;
  double x_lo = result.nodes[0].pose.x_m, x_hi = x_lo, y_lo = result.nodes[0].pose.y_m, y_hi = y_lo;
  for (const HallucinatedNode& node : result.nodes) {
    x_lo = std::min(x_lo, node.pose.x_m);
    x_hi = std::max(x_hi, node.pose.x_m);
    y_lo = std::min(y_lo, node.pose.y_m);
    y_hi = std::max(y_hi, node.pose.y_m);
  }
  const double box_x0 = x_lo - r, box_y0 = y_lo - r;
  // >= r·(1 + 1e-6): a node within r of another is at most one bin away despite rounding;
  // at most ~256 bins a side.
  const double bin_m = std::max(r, std::max(x_hi - x_lo, y_hi - y_lo) / 250.0) * (1.0 + 1e-6);
  const int bin_cols = static_cast<int>((x_hi + r - box_x0) / bin_m) + 1;
  const int bin_rows = static_cast<int>((y_hi + r - box_y0) / bin_m) + 1;
  auto bin_col = [&](double x) {
    return std::min(bin_cols - 1, static_cast<int>((x - box_x0) / bin_m));
  };
  auto bin_row = [&](double y) {
    return std::min(bin_rows - 1, static_cast<int>((y - box_y0) / bin_m));
  };
  std::vector<int>
      nearby;  // eligible base nodes in the box, grouped by bin, ascending within a bin
  std::vector<int> bin_start;  // nearby[bin_start[b] .. bin_start[b + 1]) are in bin b
  if (last_eligible > 0) {
    std::vector<int> in_box;
    for (int j = 0; j < last_eligible; ++j) {
      const Pose2d& pose = graph.nodes[j].pose;
      if (pose.x_m >= x_lo - r && pose.x_m <= x_hi + r && pose.y_m >= y_lo - r &&
          pose.y_m <= y_hi + r) {
        in_box.push_back(j);
      }
    }
    bin_start.assign(static_cast<std::size_t>(bin_cols) * bin_rows + 1, 0);
    std::vector<int> bin_of(in_box.size());
    for (std::size_t q = 0; q < in_box.size(); ++q) {
      const Pose2d& pose = graph.nodes[in_box[q]].pose;
      bin_of[q] = bin_row(pose.y_m) * bin_cols + bin_col(pose.x_m);
      ++bin_start[bin_of[q] + 1];
    }
    for (std::size_t b = 1; b < bin_start.size(); ++b) bin_start[b] += bin_start[b - 1];
    nearby.resize(in_box.size());
    std::vector<int> next(bin_start.begin(), bin_start.end() - 1);
    for (std::size_t q = 0; q < in_box.size(); ++q) nearby[next[bin_of[q]]++] = in_box[q];
  }
  for (int k = 0; k < num_new; ++k) {
    const HallucinatedNode& node = result.nodes[k];
    const int i = num_base + k;
    PoseGraphEdge chain;
    chain.from_id = i - 1;
    chain.to_id = i;
    chain.kind = EdgeKind::kOdometry;
    const Pose2d previous = k == 0 ? newest : result.nodes[k - 1].pose;
    chain.measurement = previous.Between(node.pose);
    chain.information = odometry_information * (1.0 + node.unknown_fraction);
    result.edges.push_back(chain);

    if (!(node.occupied_fraction > options.occupied_fraction_threshold)) continue;
    // Candidates in any order: the nearest `keep` by (distance, index) are unique.
    std::vector<std::pair<double, int>> candidates;  // (squared distance, j)
    if (!nearby.empty()) {
      const int col = bin_col(node.pose.x_m), row = bin_row(node.pose.y_m);
      for (int bin_r = std::max(row - 1, 0); bin_r <= std::min(row + 1, bin_rows - 1); ++bin_r) {
        for (int bin_c = std::max(col - 1, 0); bin_c <= std::min(col + 1, bin_cols - 1); ++bin_c) {
          const int b = bin_r * bin_cols + bin_c;
          for (int q = bin_start[b]; q < bin_start[b + 1]; ++q) {
            const int j = nearby[q];
            const Pose2d& other = graph.nodes[j].pose;
            const double dx = other.x_m - node.pose.x_m, dy = other.y_m - node.pose.y_m;
            const double distance_sq = dx * dx + dy * dy;
            if (distance_sq <= radius_sq) candidates.emplace_back(distance_sq, j);
          }
        }
      }
    }
    const std::size_t keep =
        std::min(candidates.size(), static_cast<std::size_t>(options.max_loop_closures_per_node));
    std::partial_sort(candidates.begin(), candidates.begin() + keep, candidates.end());
    for (std::size_t c = 0; c < keep; ++c) {
      const int j = candidates[c].second;
      PoseGraphEdge closure;
      closure.from_id = i;
      closure.to_id = j;
      closure.kind = EdgeKind::kLoopClosure;
      closure.measurement = node.pose.Between(graph.nodes[j].pose);
      closure.information = odometry_information * options.loop_closure_scale *
                            (static_cast<double>(i - j) / num_base) * node.occupied_fraction;
      result.edges.push_back(closure);
    }
  }

  result.extension.num_new_nodes = num_new;
  result.extension.edges.reserve(result.edges.size());
  for (const PoseGraphEdge& edge : result.edges) {
    result.extension.edges.push_back({edge.from_id, edge.to_id, DOptimality(edge.information)});
  }
  return result;
}

GraphExtension HallucinatePath(const PoseGraph& graph, const std::vector<Point2d>& path_m,
                               const OccupancyGrid& map, const HallucinationOptions& options) {
  return HallucinatePathDetailed(graph, path_m, map, options).extension;
}

void ValidateHallucinationOptions(const HallucinationOptions& options) {
  auto require = [](bool ok, const char* field, double value) {
    if (!ok) throw std::invalid_argument(Describe(field, value));
  };
  auto positive = [&](const char* field, double value) {
    require(std::isfinite(value) && value > 0.0, field, value);
  };
  require(options.path_cells_per_node >= 1, "path_cells_per_node", options.path_cells_per_node);
  positive("odometry_sigma_xx", options.odometry_sigma_xx);
  positive("odometry_sigma_yy", options.odometry_sigma_yy);
  positive("odometry_sigma_yawyaw", options.odometry_sigma_yawyaw);
  // Σ_odo must be positive definite for I_odo = ½·inv(Σ_odo) to exist.
  require(std::isfinite(options.odometry_sigma_xy) &&
              options.odometry_sigma_xy * options.odometry_sigma_xy <
                  options.odometry_sigma_xx * options.odometry_sigma_yy,
          "odometry_sigma_xy", options.odometry_sigma_xy);
  positive("unknown_radius_m", options.unknown_radius_m);
  positive("loop_closure_radius_m", options.loop_closure_radius_m);
  require(options.max_loop_closures_per_node >= 0, "max_loop_closures_per_node",
          options.max_loop_closures_per_node);
  require(options.exclude_newest_nodes >= 0, "exclude_newest_nodes", options.exclude_newest_nodes);
  require(std::isfinite(options.occupied_fraction_threshold) &&
              options.occupied_fraction_threshold >= 0.0 &&
              options.occupied_fraction_threshold <= 1.0,
          "occupied_fraction_threshold", options.occupied_fraction_threshold);
  require(std::isfinite(options.loop_closure_scale) && options.loop_closure_scale >= 0.0,
          "loop_closure_scale", options.loop_closure_scale);
}

}  // namespace aslam
