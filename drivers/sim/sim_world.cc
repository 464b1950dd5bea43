#include "drivers/sim/sim_world.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include <opencv2/imgproc.hpp>

// Why the fast casts equal the plain traversal bit for bit: the plain
// traversal visits cells in the order of their boundary crossings, whose
// times come from cell indices alone (ExitTime), so its state at a time t is
// a function of t (CellAt). A jump to a time t up to which the ray is known
// to cross only free cells (distance field, or discs from the previous ray
// of a sweep) lands in exactly the state the plain traversal has at t, and
// from there both compute the same entry time into the same solid cell.

namespace aslam {
namespace {

// Float rounding in the distance transform and the traversal stays far below this.
constexpr double kSkipMarginCells = 0.01;
// Shorter skips cost more than the DDA steps they replace.
constexpr uint8_t kMinSkipCells = 2;
// Rays start this far inside the stretch that free discs cover (float safety).
constexpr double kCoverageMarginCells = 1e-6;
// Free discs handed from one ray of a sweep to the next.
constexpr int kMaxDiscs = 64;

}  // namespace

namespace internal {

// A ray traversal in cell units: the ray is g(t) = g0 + t * d. Cell indices
// are kept as doubles (exact small integers) so exit times need no conversion.
struct Ray {
  double gx, gy;          // origin
  double dx, dy;          // unit direction
  double inv_dx, inv_dy;  // 1 / d; +inf for d = 0 (that axis never crosses a boundary)
  double step_x, step_y;  // -1, 0 or +1: where the next cell lies
  double exit_x, exit_y;  // a cell's exit boundary is cell + exit
  double col, row;        // the current cell
  double t;               // time of the last boundary crossing or jump
  double max_t;
  std::ptrdiff_t index;  // of (col, row) in the padded grid
  std::ptrdiff_t index_step_x, index_step_y;
};

}  // namespace internal

namespace {

using internal::Ray;

// Time at which the ray leaves `cell` along one axis. Computed from the index,
// never accumulated, so every traversal that reaches a cell agrees on it bit
// for bit; +inf when the axis has no step (then cell + 1 > origin).
inline double ExitTime(double cell, double exit, double origin, double inverse) {
  return (cell + exit - origin) * inverse;
}

// The cell along one axis once every boundary crossing at a time <= t has
// happened: the traversal state at t, whatever path reached it. The guess is
// almost always right; the loops make it exact.
inline double CellAt(double t, double origin, double direction, double inverse, double step,
                     double exit, int* cell_index) {
  // Truncation is floor for the coordinates >= 0 of free cells; the loops fix the rest.
  int index = static_cast<int>(origin + t * direction);
  double cell = index;
  const int index_step = static_cast<int>(step);
  while (ExitTime(cell, exit, origin, inverse) <= t) {
    cell += step;
    index += index_step;
  }
  while (step != 0.0 && ExitTime(cell - step, exit, origin, inverse) > t) {
    cell -= step;
    index -= index_step;
  }
  *cell_index = index;
  return cell;
}

// Moves the ray to time t, which must lie in space known to be free.
// Returns false (the ray is done, with no hit) if t is beyond max_t.
inline bool JumpTo(Ray& ray, double t, std::ptrdiff_t stride) {
  ray.t = t;
  if (t > ray.max_t) return false;
  int col, row;
  ray.col = CellAt(t, ray.gx, ray.dx, ray.inv_dx, ray.step_x, ray.exit_x, &col);
  ray.row = CellAt(t, ray.gy, ray.dy, ray.inv_dy, ray.step_y, ray.exit_y, &row);
  ray.index = (static_cast<std::ptrdiff_t>(row) + 1) * stride + (col + 1);
  return true;
}

// One Amanatides–Woo step into the next cell. Returns false once the ray has
// entered a solid cell or passed max_t.
inline bool StepToNextCell(Ray& ray, const uint8_t* codes, uint8_t solid_code) {
  const double tx = ExitTime(ray.col, ray.exit_x, ray.gx, ray.inv_dx);
  const double ty = ExitTime(ray.row, ray.exit_y, ray.gy, ray.inv_dy);
  if (tx < ty) {
    ray.t = tx;
    ray.col += ray.step_x;
    ray.index += ray.index_step_x;
  } else {
    ray.t = ty;
    ray.row += ray.step_y;
    ray.index += ray.index_step_y;
  }
  // The solid ring stops every ray inside the padded grid.
  return !(ray.t > ray.max_t) && codes[ray.index] != solid_code;
}

// A finished ray's range in cells: +inf past max_t, else the solid cell's entry time.
inline double FinishedRange(const Ray& ray) {
  if (ray.t > ray.max_t) return std::numeric_limits<double>::infinity();
  return ray.t > 0.0 ? ray.t : 0.0;  // never -0
}

// Sets the direction of a ray placed at its origin (SimWorld::PlaceRay).
inline void AimRay(Point2d unit_direction, std::ptrdiff_t stride, Ray* ray) {
  const double dx = unit_direction.x_m, dy = unit_direction.y_m;
  if (!(std::isfinite(dx) && std::isfinite(dy)) || (dx == 0.0 && dy == 0.0)) {
    std::fprintf(stderr, "SimWorld::CastRay: invalid direction (%g, %g)\n", dx, dy);
    std::abort();
  }
  Ray& r = *ray;
  r.dx = dx;
  r.dy = dy;
  r.step_x = dx > 0.0 ? 1.0 : (dx < 0.0 ? -1.0 : 0.0);
  r.step_y = dy > 0.0 ? 1.0 : (dy < 0.0 ? -1.0 : 0.0);
  r.inv_dx = r.step_x != 0.0 ? 1.0 / dx : std::numeric_limits<double>::infinity();
  r.inv_dy = r.step_y != 0.0 ? 1.0 / dy : std::numeric_limits<double>::infinity();
  r.exit_x = r.step_x >= 0.0 ? 1.0 : 0.0;
  r.exit_y = r.step_y >= 0.0 ? 1.0 : 0.0;
  r.index_step_x = static_cast<std::ptrdiff_t>(r.step_x);
  r.index_step_y = static_cast<std::ptrdiff_t>(r.step_y) * stride;
}

// An open disc (cell units, centre relative to the rays' common origin)
// that contains no point of a solid cell.
struct FreeDisc {
  double x, y, radius;
};

}  // namespace

SimWorld::SimWorld(const OccupancyGrid& map) : map_(map) {
  if (map.empty()) {
    std::fprintf(stderr, "SimWorld: empty map\n");
    std::abort();
  }
  const int width = map.width_cells(), height = map.height_cells();
  inverse_resolution_ = 1.0 / map.resolution_m();
  padded_width_ = width + 2;
  padded_height_ = height + 2;

  // Free mask (255 free, 0 solid) with a solid ring; OpenCV rows follow our rows.
  cv::Mat free_mask(padded_height_, padded_width_, CV_8UC1, cv::Scalar(0));
  std::size_t free_cells = 0;
  for (int row = 0; row < height; ++row) {
    uint8_t* out = free_mask.ptr<uint8_t>(row + 1) + 1;
    for (int col = 0; col < width; ++col) {
      const bool free = map.at({col, row}) == OccupancyGrid::kFree;
      out[col] = free ? 255 : 0;
      free_cells += free;
    }
  }
  free_area_m2_ = static_cast<double>(free_cells) * map.resolution_m() * map.resolution_m();

  // Exact Euclidean distance (cells, centre to centre) to the nearest solid cell.
  cv::Mat clearance;
  cv::distanceTransform(free_mask, clearance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

  // From any point of a cell to any point of a solid cell whose centre is D
  // away is at least D - sqrt(2) (both points lie within sqrt(2)/2 of their centres).
  code_.assign(static_cast<std::size_t>(padded_width_) * padded_height_, kSolidCode);
  for (int row = 0; row < padded_height_; ++row) {
    const uint8_t* mask = free_mask.ptr<uint8_t>(row);
    const float* dist = clearance.ptr<float>(row);
    uint8_t* code = &code_[static_cast<std::size_t>(row) * padded_width_];
    for (int col = 0; col < padded_width_; ++col) {
      if (mask[col] == 0) continue;
      const double safe = std::floor(dist[col] - M_SQRT2 - kSkipMarginCells);
      code[col] = static_cast<uint8_t>(std::clamp(safe, 0.0, kSolidCode - 1.0));
    }
  }
}

std::size_t SimWorld::PaddedIndex(int col, int row) const {
  const int padded_col = std::clamp(col + 1, 0, padded_width_ - 1);
  const int padded_row = std::clamp(row + 1, 0, padded_height_ - 1);
  return static_cast<std::size_t>(padded_row) * padded_width_ + padded_col;
}

bool SimWorld::CircleCollides(Point2d center_m, double radius_m) const {
  const double resolution = map_.resolution_m();
  const double cx = (center_m.x_m - map_.origin_m().x_m) / resolution;
  const double cy = (center_m.y_m - map_.origin_m().y_m) / resolution;
  const double r = radius_m / resolution;
  // Off the map is solid (the negated test also catches NaN).
  if (!(cx >= 0.0 && cy >= 0.0 && cx < map_.width_cells() && cy < map_.height_cells())) {
    return true;
  }
  const int center_col = static_cast<int>(cx), center_row = static_cast<int>(cy);
  const uint8_t center_code = code_[PaddedIndex(center_col, center_row)];
  if (center_code == kSolidCode) return true;
  if (center_code > r) return false;  // the common case: open space around the robot

  const int col_min = static_cast<int>(std::floor(cx - r));
  const int col_max = static_cast<int>(std::floor(cx + r));
  const int row_min = static_cast<int>(std::floor(cy - r));
  const int row_max = static_cast<int>(std::floor(cy + r));
  const double r_squared = r * r;
  for (int row = row_min; row <= row_max; ++row) {
    const double qy = std::clamp(cy, static_cast<double>(row), row + 1.0);
    for (int col = col_min; col <= col_max; ++col) {
      if (code_[PaddedIndex(col, row)] != kSolidCode) continue;
      const double qx = std::clamp(cx, static_cast<double>(col), col + 1.0);
      if ((qx - cx) * (qx - cx) + (qy - cy) * (qy - cy) < r_squared) return true;
    }
  }
  return false;
}

bool SimWorld::PlaceRay(Point2d origin_m, double max_range_m, internal::Ray* ray) const {
  Ray& r = *ray;
  r.gx = (origin_m.x_m - map_.origin_m().x_m) * inverse_resolution_;
  r.gy = (origin_m.y_m - map_.origin_m().y_m) * inverse_resolution_;
  if (!(r.gx >= 0.0 && r.gy >= 0.0 && r.gx < map_.width_cells() && r.gy < map_.height_cells())) {
    return false;  // off the map is solid
  }
  const int col = static_cast<int>(r.gx), row = static_cast<int>(r.gy);
  r.col = col;
  r.row = row;
  r.index = static_cast<std::ptrdiff_t>(row + 1) * padded_width_ + (col + 1);
  r.max_t = max_range_m * inverse_resolution_;
  r.t = 0.0;
  return code_[r.index] != kSolidCode;
}

template <bool kUseDistanceField>
double SimWorld::Cast(Point2d origin_m, Point2d unit_direction, double max_range_m) const {
  Ray ray;
  if (!PlaceRay(origin_m, max_range_m, &ray)) return 0.0;
  AimRay(unit_direction, padded_width_, &ray);
  const uint8_t* const codes = code_.data();
  while (true) {
    if constexpr (kUseDistanceField) {
      // No solid cell is entered before t + code (see the constructor).
      const uint8_t code = codes[ray.index];
      if (code >= kMinSkipCells) {
        if (!JumpTo(ray, ray.t + code, padded_width_)) break;
        continue;
      }
    }
    if (!StepToNextCell(ray, codes, kSolidCode)) break;
  }
  return FinishedRange(ray) * map_.resolution_m();
}

std::vector<double> SimWorld::CastRays(Point2d origin_m,
                                       const std::vector<Point2d>& unit_directions,
                                       double max_range_m) const {
  // Every skip certifies a free disc: radius `code` around the point it
  // skipped from. Neighbouring beams of a sweep cross mostly the same discs,
  // so each ray first jumps past the stretch of itself that the previous
  // ray's discs cover, which spares it most of its skips.
  const int count = static_cast<int>(unit_directions.size());
  std::vector<double> ranges(count, 0.0);
  Ray placed;
  if (!PlaceRay(origin_m, max_range_m, &placed)) return ranges;
  FreeDisc discs[2][kMaxDiscs];
  int num_discs[2] = {0, 0};
  int previous = 0;
  const uint8_t* const codes = code_.data();
  for (int i = 0; i < count; ++i) {
    Ray ray = placed;
    AimRay(unit_directions[i], padded_width_, &ray);
    const FreeDisc* const old_discs = discs[previous];
    FreeDisc* const new_discs = discs[1 - previous];
    int kept = 0;
    // The covered stretch [0, covered) grows disc by disc until a gap.
    double covered = 0.0;
    for (int k = 0; k < num_discs[previous]; ++k) {
      const FreeDisc& disc = old_discs[k];
      // |t*d - c| < r for t in (b - s, b + s).
      const double b = disc.x * ray.dx + disc.y * ray.dy;
      const double discriminant =
          b * b - (disc.x * disc.x + disc.y * disc.y - disc.radius * disc.radius);
      if (discriminant <= 0.0) break;
      const double s = std::sqrt(discriminant);
      if (b - s >= covered) break;
      if (b + s > covered) {
        covered = b + s;
        new_discs[kept++] = disc;
      }
    }
    bool going = covered <= kCoverageMarginCells ||
                 JumpTo(ray, covered - kCoverageMarginCells, padded_width_);
    while (going) {
      const uint8_t code = codes[ray.index];
      if (code >= kMinSkipCells) {
        if (kept < kMaxDiscs) {
          new_discs[kept++] = {ray.t * ray.dx, ray.t * ray.dy, static_cast<double>(code)};
        }
        going = JumpTo(ray, ray.t + code, padded_width_);
      } else {
        going = StepToNextCell(ray, codes, kSolidCode);
      }
    }
    ranges[i] = FinishedRange(ray) * map_.resolution_m();
    num_discs[1 - previous] = kept;
    previous = 1 - previous;
  }
  return ranges;
}

double SimWorld::CastRayAlong(Point2d origin_m, Point2d unit_direction, double max_range_m) const {
  return Cast<true>(origin_m, unit_direction, max_range_m);
}

double SimWorld::CastRayAlongPlain(Point2d origin_m, Point2d unit_direction,
                                   double max_range_m) const {
  return Cast<false>(origin_m, unit_direction, max_range_m);
}

double SimWorld::CastRay(Point2d origin_m, double angle_rad, double max_range_m) const {
  return Cast<true>(origin_m, {std::cos(angle_rad), std::sin(angle_rad)}, max_range_m);
}

double SimWorld::CastRayPlain(Point2d origin_m, double angle_rad, double max_range_m) const {
  return Cast<false>(origin_m, {std::cos(angle_rad), std::sin(angle_rad)}, max_range_m);
}

}  // namespace aslam
