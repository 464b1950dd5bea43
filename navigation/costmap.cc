#include "navigation/costmap.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

namespace aslam {
namespace {

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

Costmap::Costmap(const OccupancyGrid& map, const CostmapOptions& options)
    : options_(options),
      width_cells_(map.width_cells()),
      height_cells_(map.height_cells()),
      resolution_m_(map.resolution_m()),
      origin_m_(map.origin_m()) {
  options_.Validate();
  if (map.empty()) return;
  const std::size_t n = static_cast<std::size_t>(width_cells_) * height_cells_;
  const std::vector<int8_t>& cells = map.cells();

  // distanceTransform measures to the nearest zero pixel: obstacles are 0.
  cv::Mat free_mask(height_cells_, width_cells_, CV_8U);
  unknown_.assign(n, 0);
  bool any_obstacle = false;
  for (int row = 0; row < height_cells_; ++row) {
    uint8_t* out = free_mask.ptr<uint8_t>(row);
    const std::size_t base = static_cast<std::size_t>(row) * width_cells_;
    for (int col = 0; col < width_cells_; ++col) {
      const int8_t value = cells[base + col];
      const bool obstacle = value >= options_.occupied_threshold;
      any_obstacle |= obstacle;
      out[col] = obstacle ? 0 : 255;
      unknown_[base + col] = value < 0 ? 1 : 0;
    }
  }

  obstacle_distance_m_.resize(n);
  if (any_obstacle) {
    cv::Mat distance_cells;
    cv::distanceTransform(free_mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    for (int row = 0; row < height_cells_; ++row) {
      const float* in = distance_cells.ptr<float>(row);
      float* out = obstacle_distance_m_.data() + static_cast<std::size_t>(row) * width_cells_;
      for (int col = 0; col < width_cells_; ++col) {
        out[col] = static_cast<float>(in[col] * resolution_m_);
      }
    }
  } else {
    // OpenCV returns a large finite sentinel here; say "none" plainly.
    std::fill(obstacle_distance_m_.begin(), obstacle_distance_m_.end(),
              std::numeric_limits<float>::infinity());
  }

  // Costs from distances; float comparison so that d == radius (as stored) is inscribed.
  const float radius_m = static_cast<float>(options_.robot_radius_m);
  const float outer_m = static_cast<float>(options_.robot_radius_m + options_.inflation_margin_m);
  costs_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float d = obstacle_distance_m_[i];
    uint8_t cost;
    if (d <= 0.0f) {
      cost = kLethal;
    } else if (d <= radius_m) {
      cost = kInscribed;
    } else if (d <= outer_m) {
      cost = static_cast<uint8_t>(
          std::lround((kInscribed - 1) *
                      std::exp(-options_.cost_scaling_per_m * (d - options_.robot_radius_m))));
    } else {
      cost = kFree;
    }
    if (unknown_[i] && !options_.unknown_passable) cost = kNoGo;
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
