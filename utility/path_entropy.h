#pragma once

// U2 of the paper (eqs. 4-7), exactly as docs/architecture.md §5 fixes it: the path entropy
// along the Bresenham ray from the robot cell R to the frontier target cell n,
// a distance decay γ and the balancing factor ρ = 10^β from U1.
//
//   ray G^n    8-connected Bresenham line R -> n, both ends included; K = its cells
//   h(p)       -p log2 p - (1-p) log2 (1-p); p = 0.1 unknown, 0.45 known (free or
//              occupied); a cell off the map counts as known
//   E^n        Σ h over the ray
//   γ^n        exp(-λ d), d = Euclidean R -> n (cell centres) in metres, or in cells
//   β          digits of the integer part of U1 (1 when U1 < 1); ρ = 10^β
//   U2^n       (1 - E/K) ρ + γ

#include <vector>

#include "common/occupancy_grid.h"

namespace aslam {

// The unit of d in γ = exp(-λ d). Metres by default (docs/architecture.md §5); the authors' code
// used cells.
enum class DistanceUnit { kMeters, kCells };

struct PathEntropyOptions {
  double lambda = 0.6;  // decay rate of γ, per distance unit
  DistanceUnit distance_unit = DistanceUnit::kMeters;
  double p_unknown = 0.1;  // occupancy probability assigned to an unknown cell
  double p_known = 0.45;   // ... and to a known (free or occupied) one

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

// 8-connected Bresenham line from `from` to `to`, both included, in order.
std::vector<CellIndex> BresenhamLine(CellIndex from, CellIndex to);

// Binary entropy h(p) in bits (0 at p = 0 or 1).
double CellEntropyBits(double p);

struct RayEntropy {
  int ray_cells = 0;        // K
  int unknown_cells = 0;    // of them, unknown on the map
  double entropy_bits = 0;  // E
};

// E and K over the Bresenham ray robot -> target (cells may lie off the map).
RayEntropy PathEntropy(const OccupancyGrid& map, CellIndex robot, CellIndex target,
                       const PathEntropyOptions& options);

// β: number of digits of the integer part of u1; 1 for u1 < 1 (and for a non-finite u1).
int DigitsOfIntegerPart(double u1);

// Every term of U2 for one frontier.
struct U2Terms {
  int ray_cells = 0;             // K
  double path_entropy_bits = 0;  // E
  double mean_entropy_bits = 0;  // E/K
  double distance_m = 0;         // Euclidean robot cell -> target cell centres, metres
  double gamma = 0;              // exp(-λ d), d in the configured unit
  int beta = 1;
  double rho = 10;  // 10^β
  double u2 = 0;    // (1 - E/K) ρ + γ
};

U2Terms ComputeU2(const OccupancyGrid& map, CellIndex robot, CellIndex target, double u1,
                  const PathEntropyOptions& options);

}  // namespace aslam
