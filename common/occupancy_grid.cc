#include "common/occupancy_grid.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace aslam {

OccupancyGrid::OccupancyGrid(int width_cells, int height_cells, double resolution_m,
                             Point2d origin_m, int8_t fill)
    : width_cells_(width_cells),
      height_cells_(height_cells),
      resolution_m_(resolution_m),
      origin_m_(origin_m) {
  if (width_cells <= 0 || height_cells <= 0 || !(resolution_m > 0.0)) {
    std::fprintf(stderr, "OccupancyGrid: invalid size %dx%d at %g m/cell\n", width_cells,
                 height_cells, resolution_m);
    std::abort();
  }
  cells_.assign(static_cast<std::size_t>(width_cells) * height_cells, fill);
}

CellIndex OccupancyGrid::WorldToCell(Point2d point_m) const {
  return {static_cast<int>(std::floor((point_m.x_m - origin_m_.x_m) / resolution_m_)),
          static_cast<int>(std::floor((point_m.y_m - origin_m_.y_m) / resolution_m_))};
}

Point2d OccupancyGrid::CellCenter(CellIndex cell) const {
  return {origin_m_.x_m + (cell.col + 0.5) * resolution_m_,
          origin_m_.y_m + (cell.row + 0.5) * resolution_m_};
}

OccupancyGrid::CellCounts OccupancyGrid::CountCells() const {
  CellCounts counts;
  for (int8_t value : cells_) {
    if (value < 0) {
      ++counts.unknown;
    } else if (value == kFree) {
      ++counts.free;
    } else {
      ++counts.occupied;
    }
  }
  return counts;
}

}  // namespace aslam
