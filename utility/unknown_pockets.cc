#include "utility/unknown_pockets.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace aslam {
namespace {

constexpr double kOpen = std::numeric_limits<double>::infinity();

bool Enterable(const Costmap& costmap, CellIndex cell) {
  return costmap.IsUnknown(cell) && costmap.Traversable(cell);
}

// Labels every unknown cell of `seed`'s region (up to `cap_cells` of them) with `label` in
// `labels`; returns the region's cell count, or -1 when it is open.
long FillRegion(const OccupancyGrid& map, const Costmap& costmap, CellIndex seed, int32_t label,
                long cap_cells, const std::vector<double>& region_areas,
                std::vector<int32_t>* labels) {
  std::vector<CellIndex> stack{seed};
  (*labels)[map.LinearIndex(seed)] = label;
  long count = 0;
  bool open = false;
  while (!stack.empty() && !open) {
    const CellIndex cell = stack.back();
    stack.pop_back();
    ++count;
    if (count >= cap_cells) open = true;
    constexpr int kSteps[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& step : kSteps) {
      const CellIndex next{cell.col + step[0], cell.row + step[1]};
      if (!map.Contains(next)) {
        open = true;
        continue;
      }
      if (!Enterable(costmap, next)) continue;
      const int32_t seen = (*labels)[map.LinearIndex(next)];
      // Another label here belongs to a region left unfinished because it was open.
      if (seen != 0 && seen != label) open = open || std::isinf(region_areas[seen]);
      if (seen != 0) continue;
      (*labels)[map.LinearIndex(next)] = label;
      stack.push_back(next);
    }
  }
  return open ? -1 : count;
}

}  // namespace

std::vector<double> BorderedUnknownAreasM2(const OccupancyGrid& map, const Costmap& costmap,
                                           const std::vector<Frontier>& frontiers, double cap_m2) {
  const double cell_area_m2 = map.resolution_m() * map.resolution_m();
  const long cap_cells = std::max(1L, static_cast<long>(std::ceil(cap_m2 / cell_area_m2)));
  std::vector<int32_t> labels(map.cells().size(), 0);
  std::vector<double> region_areas{0.0};  // by label; label 0 is "not visited"
  std::vector<double> areas(frontiers.size(), 0.0);
  for (std::size_t i = 0; i < frontiers.size(); ++i) {
    for (const Point2d& point : frontiers[i].points_m) {
      const CellIndex cell = map.WorldToCell(point);
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const CellIndex next{cell.col + dc, cell.row + dr};
          if (!map.Contains(next) || !Enterable(costmap, next)) continue;
          int32_t label = labels[map.LinearIndex(next)];
          if (label == 0) {
            label = static_cast<int32_t>(region_areas.size());
            region_areas.push_back(kOpen);  // while filling: a region met unfinished is open
            const long count =
                FillRegion(map, costmap, next, label, cap_cells, region_areas, &labels);
            region_areas[label] = count < 0 ? kOpen : count * cell_area_m2;
          }
          areas[i] = std::max(areas[i], region_areas[label]);
        }
      }
    }
  }
  return areas;
}

}  // namespace aslam
