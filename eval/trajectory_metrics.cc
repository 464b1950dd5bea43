#include "eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>

namespace aslam {
namespace {

double Ratio(int64_t part, int64_t whole) {
  return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// True when a truth cell within `radius_m` of `point` (centre to centre)
// satisfies `want`; the cell containing `point` always counts.
template <typename Predicate>
bool AnyTruthCellNear(const OccupancyGrid& truth, Point2d point, double radius_m, Predicate want) {
  const CellIndex centre = truth.WorldToCell(point);
  if (want(truth.ValueOr(centre, OccupancyGrid::kUnknown))) return true;
  const double res = truth.resolution_m();
  const int reach = static_cast<int>(std::ceil(radius_m / res));
  const double radius2 = radius_m * radius_m + 1e-12;  // exact multiples of the cell count
  for (int dr = -reach; dr <= reach; ++dr) {
    for (int dc = -reach; dc <= reach; ++dc) {
      const CellIndex cell{centre.col + dc, centre.row + dr};
      const Point2d c = truth.CellCenter(cell);
      const double dx = c.x_m - point.x_m, dy = c.y_m - point.y_m;
      if (dx * dx + dy * dy <= radius2 && want(truth.ValueOr(cell, OccupancyGrid::kUnknown))) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace

std::vector<TimedPose> KeyframePoses(const PoseGraph& graph) {
  std::vector<TimedPose> poses;
  poses.reserve(graph.nodes.size());
  for (const PoseGraphNode& node : graph.nodes) poses.push_back({node.utime, node.pose});
  return poses;
}

std::optional<Pose2d> PoseAt(const std::vector<TimedPose>& samples, int64_t utime,
                             int64_t max_gap_us) {
  if (samples.empty()) return std::nullopt;
  const auto after =
      std::lower_bound(samples.begin(), samples.end(), utime,
                       [](const TimedPose& sample, int64_t t) { return sample.utime < t; });
  if (after != samples.end() && after->utime == utime) return after->pose;
  const bool has_after = after != samples.end() && after->utime - utime <= max_gap_us;
  const bool has_before = after != samples.begin() && utime - std::prev(after)->utime <= max_gap_us;
  if (has_before && has_after) {
    const TimedPose& a = *std::prev(after);
    const TimedPose& b = *after;
    const double f = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
    return Pose2d{a.pose.x_m + f * (b.pose.x_m - a.pose.x_m),
                  a.pose.y_m + f * (b.pose.y_m - a.pose.y_m),
                  WrapAngle(a.pose.yaw_rad + f * WrapAngle(b.pose.yaw_rad - a.pose.yaw_rad))};
  }
  if (has_before) return std::prev(after)->pose;
  if (has_after) return after->pose;
  return std::nullopt;
}

std::vector<TimedPose> RelativeTo(const Pose2d& anchor, const std::vector<TimedPose>& samples) {
  std::vector<TimedPose> relative;
  relative.reserve(samples.size());
  for (const TimedPose& sample : samples) {
    relative.push_back({sample.utime, anchor.Between(sample.pose)});
  }
  return relative;
}

AteResult ComputeAte(const std::vector<TimedPose>& estimate, const std::vector<TimedPose>& truth,
                     const AteOptions& options) {
  AteResult result;
  std::optional<Pose2d> truth_anchor;
  double sum_sq_m = 0.0, sum_m = 0.0, sum_sq_rad = 0.0;
  for (const TimedPose& e : estimate) {
    const std::optional<Pose2d> t = PoseAt(truth, e.utime, options.max_time_gap_us);
    if (!t) {
      ++result.unmatched;
      continue;
    }
    if (!truth_anchor) truth_anchor = *t;
    const Pose2d truth_in_map = truth_anchor->Between(*t);
    const double error_m = std::hypot(e.pose.x_m - truth_in_map.x_m, e.pose.y_m - truth_in_map.y_m);
    const double error_rad = std::abs(WrapAngle(e.pose.yaw_rad - truth_in_map.yaw_rad));
    ++result.matched;
    result.errors_m.push_back(error_m);
    sum_sq_m += error_m * error_m;
    sum_m += error_m;
    sum_sq_rad += error_rad * error_rad;
    if (error_m > result.max_m) {
      result.max_m = error_m;
      result.max_utime = e.utime;
    }
    result.yaw_max_rad = std::max(result.yaw_max_rad, error_rad);
  }
  if (result.matched > 0) {
    result.rmse_m = std::sqrt(sum_sq_m / result.matched);
    result.mean_m = sum_m / result.matched;
    result.yaw_rmse_rad = std::sqrt(sum_sq_rad / result.matched);
  }
  return result;
}

Coverage ComputeCoverage(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                         const OccupancyGrid& truth) {
  return CoverageEvaluator(truth, map_in_world).Evaluate(slam_map);
}

CoverageEvaluator::CoverageEvaluator(const OccupancyGrid& truth, const Pose2d& map_in_world) {
  // Pose2d::Transform and CellCenter written out with the rotation computed once.
  const Pose2d world_in_map = map_in_world.Inverse();
  const double c = std::cos(world_in_map.yaw_rad), s = std::sin(world_in_map.yaw_rad);
  const double truth_res = truth.resolution_m();
  const Point2d truth_origin = truth.origin_m();
  for (int row = 0; row < truth.height_cells(); ++row) {
    const double y_m = truth_origin.y_m + (row + 0.5) * truth_res;
    for (int col = 0; col < truth.width_cells(); ++col) {
      if (truth.at({col, row}) != OccupancyGrid::kFree) continue;
      const double x_m = truth_origin.x_m + (col + 0.5) * truth_res;
      truth_free_in_map_m_.push_back(
          {world_in_map.x_m + c * x_m - s * y_m, world_in_map.y_m + s * x_m + c * y_m});
    }
  }
}

Coverage CoverageEvaluator::Evaluate(const OccupancyGrid& slam_map) {
  const MapGeometry geometry{slam_map.width_cells(), slam_map.height_cells(),
                             slam_map.resolution_m(), slam_map.origin_m()};
  if (!(geometry == geometry_)) {
    // The map grew (or is the first): place the truth's free cells on its grid again.
    geometry_ = geometry;
    cell_indices_.clear();
    for (const Point2d& p : truth_free_in_map_m_) {
      // WorldToCell written out.
      const CellIndex cell{
          static_cast<int>(std::floor((p.x_m - geometry.origin_m.x_m) / geometry.resolution_m)),
          static_cast<int>(std::floor((p.y_m - geometry.origin_m.y_m) / geometry.resolution_m))};
      if (slam_map.Contains(cell)) cell_indices_.push_back(slam_map.LinearIndex(cell));
    }
    // The count does not depend on the order: read the map in memory order.
    std::sort(cell_indices_.begin(), cell_indices_.end());
  }
  Coverage result;
  result.truth_free_cells = static_cast<int64_t>(truth_free_in_map_m_.size());
  const std::vector<int8_t>& cells = slam_map.cells();
  for (const std::size_t index : cell_indices_) {
    result.truth_free_known += cells[index] != OccupancyGrid::kUnknown;
  }
  result.fraction = Ratio(result.truth_free_known, result.truth_free_cells);
  return result;
}

MapAgreement ComputeMapAgreement(const OccupancyGrid& slam_map, const Pose2d& map_in_world,
                                 const OccupancyGrid& truth, const MapAgreementOptions& options) {
  MapAgreement result;
  auto solid = [](int8_t value) { return value != OccupancyGrid::kFree; };
  auto free = [](int8_t value) { return value == OccupancyGrid::kFree; };
  for (int row = 0; row < slam_map.height_cells(); ++row) {
    for (int col = 0; col < slam_map.width_cells(); ++col) {
      const int8_t value = slam_map.at({col, row});
      const bool occupied = value >= options.occupied_min;
      const bool is_free = value >= 0 && value <= options.free_max;
      if (!occupied && !is_free) continue;
      const Point2d in_world = map_in_world.Transform(slam_map.CellCenter({col, row}));
      if (occupied) {
        ++result.slam_occupied_cells;
        if (AnyTruthCellNear(truth, in_world, options.wall_tolerance_m, solid)) {
          ++result.occupied_near_wall;
        }
      } else {
        ++result.slam_free_cells;
        if (AnyTruthCellNear(truth, in_world, options.free_tolerance_m, free)) {
          ++result.free_truly_free;
        }
      }
    }
  }
  const Coverage coverage = ComputeCoverage(slam_map, map_in_world, truth);
  result.truth_free_cells = coverage.truth_free_cells;
  result.truth_free_known = coverage.truth_free_known;
  result.occupied_precision = Ratio(result.occupied_near_wall, result.slam_occupied_cells);
  result.free_precision = Ratio(result.free_truly_free, result.slam_free_cells);
  result.coverage = coverage.fraction;
  return result;
}

}  // namespace aslam
