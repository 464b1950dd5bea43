#pragma once

// A 2D occupancy grid in the ROS convention: -1 unknown, 0..100 occupancy
// percent. Cell (col, row) covers [origin + col*res, origin + (col+1)*res) in
// x and likewise in y; row 0 is the bottom row (smallest y).

#include <cstdint>
#include <vector>

#include "common/pose2d.h"

namespace aslam {

struct CellIndex {
  int col = 0;
  int row = 0;
  bool operator==(const CellIndex& other) const { return col == other.col && row == other.row; }
  bool operator!=(const CellIndex& other) const { return !(*this == other); }
};

// Visits the cells of the 8-connected Bresenham line from `from` to `to`, both included,
// in order, while `visit(cell)` returns true. Returns false when a visit stopped it.
template <typename Visit>
bool VisitLine(CellIndex from, CellIndex to, Visit&& visit) {
  const int dx = to.col > from.col ? to.col - from.col : from.col - to.col;
  const int dy = -(to.row > from.row ? to.row - from.row : from.row - to.row);
  const int step_col = from.col < to.col ? 1 : -1;
  const int step_row = from.row < to.row ? 1 : -1;
  int error = dx + dy;
  CellIndex cell = from;
  while (true) {
    if (!visit(cell)) return false;
    if (cell == to) return true;
    const int twice = 2 * error;
    if (twice >= dy) {
      error += dy;
      cell.col += step_col;
    }
    if (twice <= dx) {
      error += dx;
      cell.row += step_row;
    }
  }
}

class OccupancyGrid {
 public:
  static constexpr int8_t kUnknown = -1;
  static constexpr int8_t kFree = 0;
  static constexpr int8_t kOccupied = 100;

  OccupancyGrid() = default;
  // Aborts on a non-positive size or resolution: callers validate user input first.
  OccupancyGrid(int width_cells, int height_cells, double resolution_m, Point2d origin_m,
                int8_t fill = kUnknown);

  int width_cells() const { return width_cells_; }
  int height_cells() const { return height_cells_; }
  double resolution_m() const { return resolution_m_; }
  // World position of the lower-left corner of cell (0, 0).
  Point2d origin_m() const { return origin_m_; }
  double width_m() const { return width_cells_ * resolution_m_; }
  double height_m() const { return height_cells_ * resolution_m_; }
  bool empty() const { return cells_.empty(); }

  bool Contains(CellIndex cell) const {
    return cell.col >= 0 && cell.row >= 0 && cell.col < width_cells_ && cell.row < height_cells_;
  }
  std::size_t LinearIndex(CellIndex cell) const {
    return static_cast<std::size_t>(cell.row) * width_cells_ + cell.col;
  }
  // The inverse of LinearIndex.
  CellIndex CellOfLinearIndex(std::size_t index) const {
    return {static_cast<int>(index % width_cells_), static_cast<int>(index / width_cells_)};
  }
  int8_t at(CellIndex cell) const { return cells_[LinearIndex(cell)]; }
  int8_t& at(CellIndex cell) { return cells_[LinearIndex(cell)]; }
  // Value of a cell, or `outside` for a cell off the grid.
  int8_t ValueOr(CellIndex cell, int8_t outside) const {
    return Contains(cell) ? at(cell) : outside;
  }

  // The cell containing a world point (may lie outside the grid).
  CellIndex WorldToCell(Point2d point_m) const;
  Point2d CellCenter(CellIndex cell) const;

  const std::vector<int8_t>& cells() const { return cells_; }
  std::vector<int8_t>& mutable_cells() { return cells_; }

  // Counts of unknown, free (== 0) and other known cells.
  struct CellCounts {
    std::size_t unknown = 0;
    std::size_t free = 0;
    std::size_t occupied = 0;  // any value in 1..100
  };
  CellCounts CountCells() const;

 private:
  int width_cells_ = 0;
  int height_cells_ = 0;
  double resolution_m_ = 0.0;
  Point2d origin_m_;
  std::vector<int8_t> cells_;
};

}  // namespace aslam
