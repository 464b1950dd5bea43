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

  if (any_obstacle) {
    cv::Mat distance(height_cells_, width_cells_, CV_32F, obstacle_distance_m_.data());
    cv::distanceTransform(free_mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    if (distance.data != reinterpret_cast<uchar*>(obstacle_distance_m_.data())) {
      Fail("distanceTransform did not write into the given buffer");
    }
  } else {
    // OpenCV returns a large finite sentinel here; say "none" plainly.
    std::fill(obstacle_distance_m_.begin(), obstacle_distance_m_.end(),
              std::numeric_limits<float>::infinity());
  }

  // Costs from distances; float comparison so that d == radius (as stored) is inscribed.
  // Distances inside the margin take few values (sqrt of an integer, in cells): the
  // exp of each is computed once, keyed by the squared distance and checked exactly.
  const double inscribed_m = options_.robot_radius_m + options_.clearance_margin_m;
  const float radius_m = static_cast<float>(inscribed_m);
  const float outer_m = static_cast<float>(inscribed_m + options_.inflation_margin_m);
  const double outer_cells = static_cast<double>(outer_m) / resolution_m_ + 2.0;
  const std::size_t table_size = static_cast<std::size_t>(std::min(outer_cells * outer_cells, 65536.0)) + 1;
  std::vector<float> table_distance(table_size, -1.0f);  // -1: empty slot (distances are >= 0)
  std::vector<uint8_t> table_cost(table_size, 0);
  auto decayed_cost = [&](float d) {
    return static_cast<uint8_t>(
        std::lround((kInscribed - 1) *
                    std::exp(-options_.cost_scaling_per_m * (d - inscribed_m))));
  };
  const bool mark_no_go = !options_.unknown_passable;
  for (std::size_t i = 0; i < n; ++i) {
    const float d_cells = obstacle_distance_m_[i];  // cells until converted below
    float d = d_cells;
    if (any_obstacle) {
      d = static_cast<float>(d_cells * resolution_m_);  // cells -> metres, as stored
      obstacle_distance_m_[i] = d;
    }
    uint8_t cost;
    if (d <= 0.0f) {
      cost = kLethal;
    } else if (d <= radius_m) {
      cost = kInscribed;
    } else if (d <= outer_m) {
      const std::size_t key = static_cast<std::size_t>(d_cells * d_cells + 0.5f);
      if (key < table_size) {
        if (table_distance[key] != d) {
          table_distance[key] = d;
          table_cost[key] = decayed_cost(d);
        }
        cost = table_cost[key];
      } else {
        cost = decayed_cost(d);
      }
    } else {
      cost = kFree;
    }
    if (mark_no_go && unknown_[i]) cost = kNoGo;
    costs_[i] = cost;
  }
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

}  // namespace aslam
