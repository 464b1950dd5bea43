#include "utility/path_entropy.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

namespace aslam {
namespace {

[[noreturn]] void ThrowBadOption(const std::string& name, double value, const std::string& why) {
  std::ostringstream out;
  out << "PathEntropyOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(out.str());
}

}  // namespace

void PathEntropyOptions::Validate() const {
  if (!(lambda >= 0.0) || !std::isfinite(lambda)) {
    ThrowBadOption("lambda", lambda, "must be finite and >= 0");
  }
  if (!(p_unknown > 0.0 && p_unknown < 1.0))
    ThrowBadOption("p_unknown", p_unknown, "must be in (0, 1)");
  if (!(p_known > 0.0 && p_known < 1.0)) ThrowBadOption("p_known", p_known, "must be in (0, 1)");
}

std::vector<CellIndex> BresenhamLine(CellIndex from, CellIndex to) {
  std::vector<CellIndex> line;
  line.reserve(
      static_cast<std::size_t>(std::max(std::abs(to.col - from.col), std::abs(to.row - from.row))) +
      1);
  VisitLine(from, to, [&](CellIndex cell) {
    line.push_back(cell);
    return true;
  });
  return line;
}

double CellEntropyBits(double p) {
  if (p <= 0.0 || p >= 1.0) return 0.0;
  return -p * std::log2(p) - (1.0 - p) * std::log2(1.0 - p);
}

RayEntropy PathEntropy(const OccupancyGrid& map, CellIndex robot, CellIndex target,
                       const PathEntropyOptions& options) {
  const double h_unknown = CellEntropyBits(options.p_unknown);
  const double h_known = CellEntropyBits(options.p_known);
  RayEntropy result;
  VisitLine(robot, target, [&](CellIndex cell) {
    ++result.ray_cells;
    // Off the map reads as known (docs/architecture.md §5): nothing there for the robot to learn by
    // going.
    if (map.ValueOr(cell, OccupancyGrid::kFree) == OccupancyGrid::kUnknown) {
      ++result.unknown_cells;
    }
    return true;
  });
  // Summed as counts times h so that E is exact for a given mix, whatever the order.
  result.entropy_bits =
      result.unknown_cells * h_unknown + (result.ray_cells - result.unknown_cells) * h_known;
  return result;
}

int DigitsOfIntegerPart(double u1) {
  if (!std::isfinite(u1) || u1 < 1.0) return 1;
  const double integer_part = std::floor(u1);
  // Exact integer arithmetic where it fits, so that 10, 100, ... get the right count.
  if (integer_part < 1e18) {
    auto value = static_cast<uint64_t>(integer_part);
    int digits = 0;
    while (value > 0) {
      value /= 10;
      ++digits;
    }
    return digits;
  }
  return static_cast<int>(std::floor(std::log10(integer_part))) + 1;
}

U2Terms ComputeU2(const OccupancyGrid& map, CellIndex robot, CellIndex target, double u1,
                  const PathEntropyOptions& options) {
  U2Terms terms;
  const RayEntropy ray = PathEntropy(map, robot, target, options);
  terms.ray_cells = ray.ray_cells;
  terms.path_entropy_bits = ray.entropy_bits;
  terms.mean_entropy_bits = ray.entropy_bits / ray.ray_cells;  // K >= 1: R itself is on the ray
  const double distance_cells = std::hypot(static_cast<double>(target.col - robot.col),
                                           static_cast<double>(target.row - robot.row));
  terms.distance_m = distance_cells * map.resolution_m();
  const double d =
      options.distance_unit == DistanceUnit::kMeters ? terms.distance_m : distance_cells;
  terms.gamma = std::exp(-options.lambda * d);
  terms.beta = DigitsOfIntegerPart(u1);
  terms.rho = std::pow(10.0, terms.beta);
  terms.u2 = (1.0 - terms.mean_entropy_bits) * terms.rho + terms.gamma;
  return terms;
}

}  // namespace aslam
