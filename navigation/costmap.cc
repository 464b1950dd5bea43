#include "navigation/costmap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

namespace aslam {
namespace {

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "costmap: %s\n", what);
  std::abort();
}

template <typename T>
[[noreturn]] void ThrowBadOption(const std::string& name, T value, const std::string& why) {
  std::ostringstream message;
  message << "CostmapOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

// Distances are centre to centre, clearances (what the DWA checks) to the obstacle cell's edge.
double InscribedCentreDistanceM(const CostmapOptions& options, double resolution_m) {
  return options.robot_radius_m + options.clearance_margin_m + 0.5 * resolution_m;
}
}  // namespace

void CostmapOptions::Validate() const {
  if (!(robot_radius_m >= 0.0) || !std::isfinite(robot_radius_m)) {
    ThrowBadOption("robot_radius_m", robot_radius_m, "must be finite and >= 0");
  }
  if (!(clearance_margin_m >= 0.0) || !std::isfinite(clearance_margin_m)) {
    ThrowBadOption("clearance_margin_m", clearance_margin_m, "must be finite and >= 0");
  }
  if (!(inflation_margin_m >= 0.0) || !std::isfinite(inflation_margin_m)) {
    ThrowBadOption("inflation_margin_m", inflation_margin_m, "must be finite and >= 0");
  }
  if (!(cost_scaling_per_m >= 0.0) || !std::isfinite(cost_scaling_per_m)) {
    ThrowBadOption("cost_scaling_per_m", cost_scaling_per_m, "must be finite and >= 0");
  }
  if (occupied_threshold < 1 || occupied_threshold > 100) {
    ThrowBadOption("occupied_threshold", occupied_threshold, "must be in 1..100");
  }
  if (unknown_cost < 0 || unknown_cost >= Costmap::kInscribed) {
    ThrowBadOption("unknown_cost", unknown_cost, "must be in 0..252");
  }
}

// The cost of a cell from its obstacle distance. Distances inside the band take
// few values (sqrt of an integer, in cells): the exp of each is computed once,
// keyed by the squared distance and checked exactly, so the cache never
// changes a result.
class Costmap::CostFunction {
 public:
  CostFunction(const CostmapOptions& options, double resolution_m)
      : options_(options),
        resolution_m_(resolution_m),
        inscribed_m_(InscribedCentreDistanceM(options, resolution_m)),
        radius_m_(static_cast<float>(inscribed_m_)),
        outer_m_(static_cast<float>(inscribed_m_ + options.inflation_margin_m)) {
    const double outer_cells = static_cast<double>(outer_m_) / resolution_m_ + 2.0;
    const std::size_t table_size =
        static_cast<std::size_t>(std::min(outer_cells * outer_cells, 65536.0)) + 1;
    table_distance_.assign(table_size, -1.0f);  // -1: empty slot (distances are >= 0)
    table_cost_.assign(table_size, 0);
  }

  float outer_m() const { return outer_m_; }

  // A distance transform's output (cells, finite) to metres as stored, and its cost.
  uint8_t FromCells(float d_cells, float* d_m) {
    const float d = static_cast<float>(d_cells * resolution_m_);  // cells -> metres, as stored
    *d_m = d;
    // Float comparison so that d == radius (as stored) is inscribed.
    if (d <= 0.0f) return kLethal;
    if (d <= radius_m_) return kInscribed;
    if (d > outer_m_) return kFree;
    const std::size_t key = static_cast<std::size_t>(d_cells * d_cells + 0.5f);
    if (key >= table_distance_.size()) return DecayedCost(d);
    if (table_distance_[key] != d) {
      table_distance_[key] = d;
      table_cost_[key] = DecayedCost(d);
    }
    return table_cost_[key];
  }

  // The same from a stored distance (metres, or +inf); equal to FromCells for
  // the distance FromCells stored.
  uint8_t FromMetres(float d) const {
    if (d <= 0.0f) return kLethal;
    if (d <= radius_m_) return kInscribed;
    if (d > outer_m_) return kFree;
    return DecayedCost(d);
  }

 private:
  uint8_t DecayedCost(float d) const {
    return static_cast<uint8_t>(std::lround(
        (kInscribed - 1) * std::exp(-options_.cost_scaling_per_m * (d - inscribed_m_))));
  }

  const CostmapOptions& options_;
  const double resolution_m_;
  const double inscribed_m_;
  const float radius_m_;
  const float outer_m_;
  std::vector<float> table_distance_;
  std::vector<uint8_t> table_cost_;
};

Costmap::Costmap(const OccupancyGrid& map, const CostmapOptions& options) { Rebuild(map, options); }

void Costmap::Rebuild(const OccupancyGrid& map, const CostmapOptions& options) {
  options.Validate();
  options_ = options;
  width_cells_ = map.width_cells();
  height_cells_ = map.height_cells();
  resolution_m_ = map.resolution_m();
  origin_m_ = map.origin_m();
  if (map.empty()) {
    costs_.clear();
    unknown_.clear();
    obstacle_distance_m_.clear();
    return;
  }
  const std::size_t n = static_cast<std::size_t>(width_cells_) * height_cells_;
  const std::vector<int8_t>& cells = map.cells();
  costs_.resize(n);
  unknown_.resize(n);
  obstacle_distance_m_.resize(n);

  // distanceTransform measures to the nearest zero pixel: obstacles are 0. The
  // mask lives in costs_ (overwritten with the costs below) and the transform
  // writes straight into obstacle_distance_m_: no temporary images.
  cv::Mat free_mask(height_cells_, width_cells_, CV_8U, costs_.data());
  const int8_t occupied = static_cast<int8_t>(options_.occupied_threshold);
  uint8_t any_obstacle = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int8_t value = cells[i];
    const uint8_t obstacle = value >= occupied;
    any_obstacle |= obstacle;
    costs_[i] = obstacle ? 0 : 255;
    unknown_[i] = value < 0;
  }

  const bool mark_no_go = !options_.unknown_passable;
  if (!any_obstacle) {
    // OpenCV returns a large finite sentinel here; say "none" plainly.
    std::fill(obstacle_distance_m_.begin(), obstacle_distance_m_.end(),
              std::numeric_limits<float>::infinity());
    for (std::size_t i = 0; i < n; ++i) costs_[i] = mark_no_go && unknown_[i] ? kNoGo : kFree;
    return;
  }
  cv::Mat distance(height_cells_, width_cells_, CV_32F, obstacle_distance_m_.data());
  cv::distanceTransform(free_mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  if (distance.data != reinterpret_cast<uchar*>(obstacle_distance_m_.data())) {
    Fail("distanceTransform did not write into the given buffer");
  }
  CostFunction cost(options_, resolution_m_);
  for (std::size_t i = 0; i < n; ++i) {
    float& d = obstacle_distance_m_[i];  // cells until converted
    const uint8_t value = cost.FromCells(d, &d);
    costs_[i] = mark_no_go && unknown_[i] ? kNoGo : value;
  }
}

int Costmap::BandCells() const {
  // A recomputed cell's cost depends on obstacles at d_cells * resolution <=
  // outer (as floats), so d_cells < ceil(outer / resolution) + 1.
  const double outer_m = static_cast<float>(InscribedCentreDistanceM(options_, resolution_m_) +
                                            options_.inflation_margin_m);
  return static_cast<int>(std::ceil(outer_m / resolution_m_)) + 1;
}

namespace {

bool SameOptions(const CostmapOptions& a, const CostmapOptions& b) {
  return a.robot_radius_m == b.robot_radius_m && a.clearance_margin_m == b.clearance_margin_m &&
         a.inflation_margin_m == b.inflation_margin_m &&
         a.cost_scaling_per_m == b.cost_scaling_per_m &&
         a.occupied_threshold == b.occupied_threshold && a.unknown_passable == b.unknown_passable &&
         a.unknown_cost == b.unknown_cost;
}

}  // namespace

bool Costmap::GrowInto(const OccupancyGrid& map, std::vector<Box>* boxes) {
  // Any whole-cell offset keeps the layers a valid costmap of the old map
  // embedded in the new grid (cells are compared below); the mapper's growth
  // keeps cells in place, so its offset is the origin shift.
  const double shift_col = (origin_m_.x_m - map.origin_m().x_m) / resolution_m_;
  const double shift_row = (origin_m_.y_m - map.origin_m().y_m) / resolution_m_;
  if (!(std::abs(shift_col) < 1e6) || !(std::abs(shift_row) < 1e6)) return false;
  const int dc = static_cast<int>(std::lround(shift_col));
  const int dr = static_cast<int>(std::lround(shift_row));
  const int new_width = map.width_cells();
  const int new_height = map.height_cells();
  if (std::abs(shift_col - dc) > 1e-3 || std::abs(shift_row - dr) > 1e-3 || dc < 0 || dr < 0 ||
      dc + width_cells_ > new_width || dr + height_cells_ > new_height) {
    return false;
  }
  const std::size_t n = static_cast<std::size_t>(new_width) * new_height;
  std::vector<uint8_t> costs(n, options_.unknown_passable ? kFree : kNoGo);
  std::vector<uint8_t> unknown(n, 1);
  std::vector<float> distance(n, std::numeric_limits<float>::infinity());
  for (int row = 0; row < height_cells_; ++row) {
    const std::size_t from = static_cast<std::size_t>(row) * width_cells_;
    const std::size_t to = static_cast<std::size_t>(row + dr) * new_width + dc;
    std::copy_n(costs_.begin() + from, width_cells_, costs.begin() + to);
    std::copy_n(unknown_.begin() + from, width_cells_, unknown.begin() + to);
    std::copy_n(obstacle_distance_m_.begin() + from, width_cells_, distance.begin() + to);
  }
  costs_.swap(costs);
  unknown_.swap(unknown);
  obstacle_distance_m_.swap(distance);

  // New cells near the old grid may be near its obstacles: recompute them.
  const Box old{dc, dr, dc + width_cells_, dr + height_cells_};
  const int band = BandCells();
  const Box ring{std::max(old.col0 - band, 0), std::max(old.row0 - band, 0),
                 std::min(old.col1 + band, new_width), std::min(old.row1 + band, new_height)};
  const Box strips[] = {{ring.col0, ring.row0, ring.col1, old.row0},
                        {ring.col0, old.row1, ring.col1, ring.row1},
                        {ring.col0, old.row0, old.col0, old.row1},
                        {old.col1, old.row0, ring.col1, old.row1}};
  for (const Box& strip : strips) {
    if (strip.col0 < strip.col1 && strip.row0 < strip.row1) boxes->push_back(strip);
  }
  width_cells_ = new_width;
  height_cells_ = new_height;
  origin_m_ = map.origin_m();
  return true;
}

void Costmap::RecomputeBox(const OccupancyGrid& map, const Box& box, int band, CostFunction& cost) {
  const Box window{std::max(box.col0 - band, 0), std::max(box.row0 - band, 0),
                   std::min(box.col1 + band, width_cells_),
                   std::min(box.row1 + band, height_cells_)};
  const int window_width = window.col1 - window.col0;
  const int window_height = window.row1 - window.row0;
  const int8_t occupied = static_cast<int8_t>(options_.occupied_threshold);
  std::vector<uint8_t> mask(static_cast<std::size_t>(window_width) * window_height);
  uint8_t any_obstacle = 0;
  for (int row = window.row0; row < window.row1; ++row) {
    const int8_t* in = map.cells().data() + static_cast<std::size_t>(row) * width_cells_;
    uint8_t* out = mask.data() + static_cast<std::size_t>(row - window.row0) * window_width;
    for (int col = window.col0; col < window.col1; ++col) {
      const uint8_t obstacle = in[col] >= occupied;
      any_obstacle |= obstacle;
      out[col - window.col0] = obstacle ? 0 : 255;
    }
  }
  const bool mark_no_go = !options_.unknown_passable;
  if (!any_obstacle) {
    // Nothing within the band of any cell of the box.
    for (int row = box.row0; row < box.row1; ++row) {
      const std::size_t begin = static_cast<std::size_t>(row) * width_cells_;
      for (std::size_t i = begin + box.col0; i < begin + box.col1; ++i) {
        obstacle_distance_m_[i] = std::numeric_limits<float>::infinity();
        costs_[i] = mark_no_go && unknown_[i] ? kNoGo : kFree;
      }
    }
    return;
  }
  std::vector<float> window_distance(mask.size());
  cv::Mat distance(window_height, window_width, CV_32F, window_distance.data());
  cv::distanceTransform(cv::Mat(window_height, window_width, CV_8U, mask.data()), distance,
                        cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  if (distance.data != reinterpret_cast<uchar*>(window_distance.data())) {
    Fail("distanceTransform did not write into the given buffer");
  }
  // Within the band the nearest obstacle lies in the window, and the transform
  // gives the same float as over the whole map: sqrt of the exact squared
  // distance in cells (see kMaxIncrementalCells). Beyond the band the
  // window's distance is no smaller than the true one, so the cost is kFree
  // either way.
  for (int row = box.row0; row < box.row1; ++row) {
    const std::size_t begin = static_cast<std::size_t>(row) * width_cells_;
    const float* d_cells = window_distance.data() +
                           static_cast<std::size_t>(row - window.row0) * window_width - window.col0;
    for (int col = box.col0; col < box.col1; ++col) {
      const std::size_t i = begin + col;
      const uint8_t value = cost.FromCells(d_cells[col], &obstacle_distance_m_[i]);
      costs_[i] = mark_no_go && unknown_[i] ? kNoGo : value;
    }
  }
}

Costmap::UpdateKind Costmap::Update(const OccupancyGrid& map, const CostmapOptions& options) {
  // OpenCV's precise transform (Felzenszwalb's lower envelope of parabolas)
  // adds integers exactly in float, and returns sqrtf of the chosen parabola's
  // integer value; its float breakpoints choose the nearest obstacle (or one
  // at the same distance) while a row's length n has n * 2^-23 < 1 / (2n),
  // n < 2048, so a window and the whole map agree bit for bit. Larger maps
  // (with margin) rebuild.
  constexpr int kMaxIncrementalCells = 2000;
  if (map.empty() || costs_.empty() || !SameOptions(options, options_) ||
      map.resolution_m() != resolution_m_ || map.width_cells() > kMaxIncrementalCells ||
      map.height_cells() > kMaxIncrementalCells) {
    Rebuild(map, options);
    return UpdateKind::kFull;
  }
  std::vector<Box> boxes;
  const bool same_geometry =
      map.width_cells() == width_cells_ && map.height_cells() == height_cells_ &&
      map.origin_m().x_m == origin_m_.x_m && map.origin_m().y_m == origin_m_.y_m;
  if (!same_geometry && !GrowInto(map, &boxes)) {
    Rebuild(map, options);
    return UpdateKind::kFull;
  }

  // Cells whose obstacle status changed, by tile (their bounds within it);
  // unknown status is a per-cell matter, updated here.
  constexpr int kTileCells = 32;
  const int width = width_cells_;
  const int height = height_cells_;
  const int tiles_across = (width + kTileCells - 1) / kTileCells;
  const int tiles_down = (height + kTileCells - 1) / kTileCells;
  std::vector<Box> changed(static_cast<std::size_t>(tiles_across) * tiles_down,
                           Box{width, height, -1, -1});  // inclusive bounds; empty
  std::vector<std::size_t> unknown_changed;
  const bool mark_no_go = !options_.unknown_passable;
  const int8_t occupied = static_cast<int8_t>(options_.occupied_threshold);
  const int8_t* cells = map.cells().data();
  bool any_obstacle_change = false;
  bool any_unknown_change = false;
  for (int row = 0; row < height; ++row) {
    const std::size_t begin = static_cast<std::size_t>(row) * width;
    const int8_t* in = cells + begin;
    const uint8_t* cost = costs_.data() + begin;
    uint8_t* unknown = unknown_.data() + begin;
    uint8_t obstacle_diff = 0;
    uint8_t unknown_diff = 0;
    for (int col = 0; col < width; ++col) {  // vectorized: compare only
      obstacle_diff |= static_cast<uint8_t>((in[col] >= occupied) != (cost[col] == kLethal));
      unknown_diff |= static_cast<uint8_t>((in[col] < 0) != (unknown[col] != 0));
    }
    if (obstacle_diff) {
      any_obstacle_change = true;
      Box* tiles = changed.data() + static_cast<std::size_t>(row / kTileCells) * tiles_across;
      for (int col = 0; col < width; ++col) {
        if ((in[col] >= occupied) == (cost[col] == kLethal)) continue;
        Box& tile = tiles[col / kTileCells];
        tile.col0 = std::min(tile.col0, col);
        tile.col1 = std::max(tile.col1, col);
        tile.row0 = std::min(tile.row0, row);
        tile.row1 = std::max(tile.row1, row);
      }
    }
    if (unknown_diff) {
      any_unknown_change = true;
      for (int col = 0; col < width; ++col) {
        const uint8_t now = in[col] < 0;
        if (now == unknown[col]) continue;
        unknown[col] = now;
        if (mark_no_go) unknown_changed.push_back(begin + col);
      }
    }
  }
  if (!any_obstacle_change && !any_unknown_change && boxes.empty()) return UpdateKind::kUnchanged;

  // The cells whose cost may change: the changed cells' tiles' bounds grown by the band.
  const int band = BandCells();
  if (any_obstacle_change) {
    for (const Box& tile : changed) {
      if (tile.col1 < 0) continue;
      boxes.push_back({std::max(tile.col0 - band, 0), std::max(tile.row0 - band, 0),
                       std::min(tile.col1 + 1 + band, width),
                       std::min(tile.row1 + 1 + band, height)});
    }
  }
  // Merge boxes while that shrinks the total transform window.
  auto window_area = [&](const Box& box) {
    const int across = std::min(box.col1 + band, width) - std::max(box.col0 - band, 0);
    const int down = std::min(box.row1 + band, height) - std::max(box.row0 - band, 0);
    return static_cast<std::size_t>(across) * static_cast<std::size_t>(down);
  };
  auto merged = [](const Box& a, const Box& b) {
    return Box{std::min(a.col0, b.col0), std::min(a.row0, b.row0), std::max(a.col1, b.col1),
               std::max(a.row1, b.row1)};
  };
  constexpr std::size_t kMaxBoxes = 64;
  if (boxes.size() > kMaxBoxes) {
    Box all = boxes.front();
    for (const Box& box : boxes) all = merged(all, box);
    boxes.assign(1, all);
  }
  for (bool again = true; again;) {
    again = false;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        const Box both = merged(boxes[i], boxes[j]);
        if (window_area(both) <= window_area(boxes[i]) + window_area(boxes[j])) {
          boxes[i] = both;
          boxes[j] = boxes.back();
          boxes.pop_back();
          again = true;
          j = i;  // boxes[i] grew: compare it with all the others again
        }
      }
    }
  }
  std::size_t total_window = 0;
  for (const Box& box : boxes) total_window += window_area(box);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (total_window > n / 2) {
    Rebuild(map, options);
    return UpdateKind::kFull;
  }

  CostFunction cost(options_, resolution_m_);
  for (const Box& box : boxes) RecomputeBox(map, box, band, cost);
  // Cells that only became known or unknown keep their distance: with stored
  // distances exact within the band and beyond it otherwise, their cost is
  // the distance's cost or kNoGo.
  for (std::size_t i : unknown_changed) {
    costs_[i] = unknown_[i] ? kNoGo : cost.FromMetres(obstacle_distance_m_[i]);
  }
  return UpdateKind::kIncremental;
}

CellIndex Costmap::WorldToCell(Point2d point_m) const {
  return {static_cast<int>(std::floor((point_m.x_m - origin_m_.x_m) / resolution_m_)),
          static_cast<int>(std::floor((point_m.y_m - origin_m_.y_m) / resolution_m_))};
}

Point2d Costmap::CellCenter(CellIndex cell) const {
  return {origin_m_.x_m + (cell.col + 0.5) * resolution_m_,
          origin_m_.y_m + (cell.row + 0.5) * resolution_m_};
}

uint8_t Costmap::cost(CellIndex cell) const {
  return Contains(cell) ? costs_[LinearIndex(cell)] : kNoGo;
}

bool Costmap::IsUnknown(CellIndex cell) const {
  return Contains(cell) && unknown_[LinearIndex(cell)] != 0;
}

double Costmap::ObstacleDistanceM(CellIndex cell) const {
  return Contains(cell) ? obstacle_distance_m_[LinearIndex(cell)] : 0.0;
}

std::optional<OccupancyGrid> WithPlanningObstacles(const OccupancyGrid& map,
                                                   const PlanningObstacles& obstacles,
                                                   int64_t utime) {
  constexpr int64_t kMaxAgeUs = 10'000'000;
  if (obstacles.points_m.empty() || utime - obstacles.utime > kMaxAgeUs) return std::nullopt;
  OccupancyGrid marked = map;
  for (const Point2d& point : obstacles.points_m) {
    const CellIndex cell = marked.WorldToCell(point);
    if (marked.Contains(cell))
      marked.mutable_cells()[marked.LinearIndex(cell)] = OccupancyGrid::kOccupied;
  }
  return marked;
}

}  // namespace aslam
