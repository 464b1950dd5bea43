#include "navigation/global_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <utility>

namespace aslam {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kSqrt2 = 1.41421356237309504880f;
constexpr uint16_t kUnknownBit = 1u << 8;
constexpr uint16_t kEscapeBit = 1u << 9;
constexpr uint8_t kSettledBit = 1;
constexpr uint8_t kTargetBit = 2;
// A*'s heuristic is this fraction of the octile distance to the goal: < 1 keeps
// every key step >= 1 - this (the bucket width; see Search), and near 1 prunes most.
constexpr float kHeuristicWeight = 0.95f;

template <typename T>
[[noreturn]] void ThrowBadOption(const std::string& name, T value, const std::string& why) {
  std::ostringstream message;
  message << "GlobalPlannerOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(message.str());
}

// The traversable cells 4-connected to a traversable `start`, when they are at most
// kStartPocketMaxCells: a pocket (e.g. between a pillar and a wall, whose gaps the inscribed
// zone closes) that the robot can only have entered, and only leave, through inscribed cells.
// Empty when the start's component is larger.

std::vector<CellIndex> StartPocket(const Costmap& costmap, CellIndex start) {
  std::vector<CellIndex> pocket{start};
  std::unordered_set<std::size_t> seen{costmap.LinearIndex(start)};
  for (std::size_t next = 0; next < pocket.size(); ++next) {
    const CellIndex cell = pocket[next];
    for (const auto& [dc, dr] :
         {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
      const CellIndex neighbour{cell.col + dc, cell.row + dr};
      if (!costmap.Contains(neighbour) || costmap.cost(neighbour) >= Costmap::kInscribed) continue;
      if (!seen.insert(costmap.LinearIndex(neighbour)).second) continue;
      if (pocket.size() >= kStartPocketMaxCells) return {};
      pocket.push_back(neighbour);
    }
  }
  return pocket;
}

}  // namespace

void GlobalPlannerOptions::Validate() const {
  if (!(cost_weight >= 0.0) || !std::isfinite(cost_weight)) {
    ThrowBadOption("cost_weight", cost_weight, "must be finite and >= 0");
  }
  if (!(start_escape_m >= 0.0) || !std::isfinite(start_escape_m)) {
    ThrowBadOption("start_escape_m", start_escape_m, "must be finite and >= 0");
  }
}

// ---------------------------------------------------------------------------
// ShortestPathTree

int32_t ShortestPathTree::PaddedIndex(CellIndex cell) const {
  if (cell.col < 0 || cell.row < 0 || cell.col >= width_cells_ || cell.row >= height_cells_) {
    return -1;
  }
  return (cell.row + 1) * padded_width_ + cell.col + 1;
}

CellIndex ShortestPathTree::CellOf(int32_t padded_index) const {
  return {padded_index % padded_width_ - 1, padded_index / padded_width_ - 1};
}

bool ShortestPathTree::SameGrid(const Costmap& costmap) const {
  return width_cells_ == costmap.width_cells() && height_cells_ == costmap.height_cells() &&
         resolution_m_ == costmap.resolution_m() && origin_m_.x_m == costmap.origin_m().x_m &&
         origin_m_.y_m == costmap.origin_m().y_m && !cost_.empty();
}

bool ShortestPathTree::Reachable(CellIndex cell) const {
  const int32_t p = PaddedIndex(cell);
  return p >= 0 && (settled_[p] & kSettledBit) != 0;
}

double ShortestPathTree::CostTo(CellIndex cell) const {
  return Reachable(cell) ? static_cast<double>(cost_[PaddedIndex(cell)])
                         : std::numeric_limits<double>::infinity();
}

double ShortestPathTree::PathLengthM(CellIndex cell) const {
  return Reachable(cell) ? static_cast<double>(length_cells_[PaddedIndex(cell)]) * resolution_m_
                         : std::numeric_limits<double>::infinity();
}

std::optional<GlobalPath> ShortestPathTree::PathTo(CellIndex cell) const {
  if (!Reachable(cell)) return std::nullopt;
  const int32_t goal = PaddedIndex(cell);
  GlobalPath path;
  for (int32_t p = goal; p >= 0; p = parent_[p]) path.cells.push_back(CellOf(p));
  std::reverse(path.cells.begin(), path.cells.end());
  path.points_m.reserve(path.cells.size());
  for (const CellIndex& c : path.cells) {
    path.points_m.push_back({origin_m_.x_m + (c.col + 0.5) * resolution_m_,
                             origin_m_.y_m + (c.row + 0.5) * resolution_m_});
  }
  path.length_m = PathLengthM(cell);
  path.cost = CostTo(cell);
  return path;
}

// ---------------------------------------------------------------------------
// GlobalPlanner

GlobalPlanner::GlobalPlanner(GlobalPlannerOptions options) : options_(options) {
  options_.Validate();
}

ShortestPathTree GlobalPlanner::Search(const Costmap& costmap, CellIndex start,
                                       const std::vector<CellIndex>& targets) const {
  ShortestPathTree tree;
  Search(costmap, start, targets, &tree);
  return tree;
}

void GlobalPlanner::Search(const Costmap& costmap, CellIndex start,
                           const std::vector<CellIndex>& targets, ShortestPathTree* tree) const {
  SearchImpl(costmap, start, targets, std::nullopt, tree);
}

void GlobalPlanner::DistancesToGoal(const Costmap& costmap, CellIndex goal, CellIndex robot,
                                    ShortestPathTree* field) const {
  SearchImpl(costmap, goal, {robot}, std::nullopt, field, nullptr, CostModel::kLowerBound);
}

void GlobalPlanner::SearchImpl(const Costmap& costmap, CellIndex start,
                               const std::vector<CellIndex>& targets,
                               std::optional<CellIndex> heuristic_goal, ShortestPathTree* tree,
                               const ShortestPathTree* goal_distances, CostModel model) const {
  const int width = costmap.width_cells();
  const int height = costmap.height_cells();
  const int padded_width = width + 2;
  const std::size_t padded_size = static_cast<std::size_t>(padded_width) * (height + 2);
  ShortestPathTree& t = *tree;
  t.start_ = start;
  t.width_cells_ = width;
  t.height_cells_ = height;
  t.padded_width_ = padded_width;
  t.resolution_m_ = costmap.resolution_m();
  t.origin_m_ = costmap.origin_m();
  t.settled_count_ = 0;
  t.stopped_at_cost_ = kInf;
  t.cost_.assign(padded_size, kInf);
  t.settled_.assign(padded_size, 0);
  t.length_cells_.resize(padded_size);  // read only where settled: no reset needed
  t.parent_.resize(padded_size);

  // Cell classes: the border reads kNoGo, so neighbour loops need no bounds checks.
  std::vector<uint16_t>& cell_class = t.cell_class_;
  cell_class.assign(padded_size, Costmap::kNoGo);
  const std::vector<uint8_t>& costs = costmap.costs();
  const std::vector<uint8_t>& unknown = costmap.unknown_mask();
  for (int row = 0; row < height; ++row) {
    const std::size_t in = static_cast<std::size_t>(row) * width;
    uint16_t* out = cell_class.data() + static_cast<std::size_t>(row + 1) * padded_width + 1;
    for (int col = 0; col < width; ++col) {
      out[col] = static_cast<uint16_t>(costs[in + col] | (unknown[in + col] ? kUnknownBit : 0));
    }
  }

  const int32_t start_index = t.PaddedIndex(start);
  if (start_index < 0) return;

  // Start escape: inscribed cells near a start that is itself not traversable, or near the
  // pocket of traversable cells the start is shut in (the robot got there, so it can leave).
  if (options_.start_escape_m > 0.0 && model != CostModel::kLowerBound) {
    std::vector<CellIndex> escape_from;
    double escape_m = options_.start_escape_m;
    if (costs[costmap.LinearIndex(start)] >= Costmap::kInscribed) {
      escape_from.push_back(start);
    } else {
      escape_from = StartPocket(costmap, start);
      // A gap's inscribed cells reach an inscribed radius into the pocket and out of it.
      const CostmapOptions& c = costmap.options();
      escape_m += c.robot_radius_m + c.clearance_margin_m;
    }
    const double radius_cells = escape_m / costmap.resolution_m();
    // Where the robot's body fits, or no closer to an obstacle than it already is (the DWA's
    // rule inside its margin): a hole in a wall narrower than the robot never opens.
    const double half_cell_m = 0.5 * costmap.resolution_m();
    const double min_clearance_m =
        std::min(costmap.options().robot_radius_m, costmap.ObstacleDistanceM(start) - half_cell_m) -
        1e-9;
    const int reach = static_cast<int>(std::floor(radius_cells));
    for (const CellIndex& from : escape_from) {
      for (int dr = -reach; dr <= reach; ++dr) {
        for (int dc = -reach; dc <= reach; ++dc) {
          const CellIndex cell{from.col + dc, from.row + dr};
          if (!costmap.Contains(cell) || dc * dc + dr * dr > radius_cells * radius_cells) continue;
          if (costmap.cost(cell) == Costmap::kInscribed &&
              costmap.ObstacleDistanceM(cell) - half_cell_m >= min_clearance_m) {
            cell_class[t.PaddedIndex(cell)] |= kEscapeBit;
          }
        }
      }
    }
  }

  // Step multiplier per class: 1 + w * (cost + unknown penalty) / 253, +inf = never enter.
  std::array<float, 1024> multiplier;
  const double weight = options_.cost_weight / Costmap::kInscribed;
  const int unknown_cost = costmap.options().unknown_cost;
  for (int code = 0; code < 1024; ++code) {
    const int cell_cost = code & 0xff;
    const int penalty = (code & kUnknownBit) ? unknown_cost : 0;
    if (model == CostModel::kLowerBound) {
      // The unknown penalty goes once the cell is seen. The inscribed zone stays out: a gap the
      // robot does not fit through would otherwise make a long detour look short.
      multiplier[code] =
          cell_cost >= Costmap::kInscribed ? kInf : static_cast<float>(1.0 + weight * cell_cost);
    } else if (code & kEscapeBit) {
      multiplier[code] = static_cast<float>(1.0 + weight * (Costmap::kInscribed + penalty));
    } else if (cell_cost >= Costmap::kInscribed) {
      multiplier[code] = kInf;
    } else {
      multiplier[code] = static_cast<float>(1.0 + weight * (cell_cost + penalty));
    }
  }

  // Targets to wait for: on the map and enterable (others can never be settled).
  std::size_t targets_left = 0;
  for (const CellIndex& target : targets) {
    const int32_t p = t.PaddedIndex(target);
    if (p < 0 || (p != start_index && multiplier[cell_class[p]] == kInf)) continue;
    if (!(t.settled_[p] & kTargetBit)) {
      t.settled_[p] |= kTargetBit;
      ++targets_left;
    }
  }
  const bool from_goal = model == CostModel::kLowerBound;
  const bool stop_early = targets_left > 0 && !from_goal;
  // From the goal: settle on to 1.25 x the robot's cost, plus a margin, once it is settled.
  constexpr float kFieldMarginCells = 20.0f;
  float stop_above_cost = kInf;

  float* cost = t.cost_.data();
  float* length = t.length_cells_.data();
  int32_t* parent = t.parent_.data();
  uint8_t* settled = t.settled_.data();
  const uint16_t* cls = cell_class.data();
  const float* mult = multiplier.data();
  // Orthogonal neighbours E, W, N, S; diagonal k lies between orthogonals diag_sides[k].
  const int32_t orth[4] = {1, -1, padded_width, -padded_width};
  const int32_t diag[4] = {padded_width + 1, padded_width - 1, -padded_width + 1,
                           -padded_width - 1};
  const int diag_sides[4][2] = {{0, 2}, {1, 2}, {0, 3}, {1, 3}};

  // Cells are queued by key = cost + h, where h is 0 (Dijkstra) or, towards a
  // single goal, kHeuristicWeight * the octile distance to it in cells (A*).
  // Every step costs at least its octile length (multipliers are >= 1), so a
  // step raises the key by at least (1 - kHeuristicWeight) * 1 = the bucket
  // width: a cell popped from bucket k can only lower keys to >= bucket k + 1,
  // so every cell in the current bucket already has its final cost and the
  // bucket may be drained in any order (Dinitz's refinement of Dial's
  // algorithm). Exact for float costs, O(1) per push and pop. Buckets are used
  // circularly; there are more of them than the largest key step spans.
  const float bucket_width = heuristic_goal ? 1.0f - kHeuristicWeight : 1.0f;
  const float inverse_width = 1.0f / bucket_width;
  float max_edge = 1.0f;
  for (float m : multiplier) {
    if (m != kInf) max_edge = std::max(max_edge, kSqrt2 * m);
  }
  // A key step is at most the edge cost + the heuristic's change (<= sqrt 2).
  const float max_key_step = (max_edge + kSqrt2) * inverse_width;
  std::size_t bucket_count = 4;
  while (bucket_count < static_cast<std::size_t>(max_key_step) + 3) bucket_count *= 2;
  const std::size_t bucket_mask = bucket_count - 1;
  std::vector<std::vector<int32_t>>& buckets = t.buckets_;
  if (buckets.size() < bucket_count) buckets.resize(bucket_count);
  for (auto& bucket : buckets) bucket.clear();
  // h per padded index; the goal's padded coordinates (the border shifts both alike).
  const int goal_col = heuristic_goal ? heuristic_goal->col + 1 : 0;
  const int goal_row = heuristic_goal ? heuristic_goal->row + 1 : 0;
  const bool use_heuristic = heuristic_goal.has_value();
  // A field from an older costmap is a consistent heuristic except where an obstacle has gone
  // since (there it may drop or jump): keys are then clamped into the queue's window and
  // settled cells stay settled, so the path is valid though maybe not the cheapest.
  const float* field = nullptr;
  const uint8_t* field_settled = nullptr;
  float field_floor = 0.0f;  // every cell the field did not settle costs at least this
  if (use_heuristic && goal_distances != nullptr && goal_distances->SameGrid(costmap) &&
      goal_distances->start() == *heuristic_goal) {
    field = goal_distances->cost_.data();
    field_settled = goal_distances->settled_.data();
    if (goal_distances->stopped_at_cost_ != kInf) field_floor = goal_distances->stopped_at_cost_;
  }
  auto heuristic = [&](int32_t p) -> float {
    if (!use_heuristic) return 0.0f;
    if (field != nullptr && (field_settled[p] & kSettledBit)) return kHeuristicWeight * field[p];
    const int dc = std::abs(p % padded_width - goal_col);
    const int dr = std::abs(p / padded_width - goal_row);
    return kHeuristicWeight * std::max(field_floor, static_cast<float>(std::max(dc, dr)) +
                                                        (kSqrt2 - 1.0f) * std::min(dc, dr));
  };
  // Buckets are numbered absolutely and used circularly (index = number & mask).
  std::size_t current = static_cast<std::size_t>(heuristic(start_index) * inverse_width);
  auto bucket_of = [&](float key) {
    std::size_t number = static_cast<std::size_t>(key * inverse_width);
    if (field != nullptr) number = std::clamp(number, current, current + bucket_mask);
    return number & bucket_mask;
  };

  cost[start_index] = 0.0f;
  length[start_index] = 0.0f;
  parent[start_index] = -1;
  buckets[bucket_of(heuristic(start_index))].push_back(start_index);
  std::size_t queued = 1;  // entries in all buckets, stale ones included
  std::size_t settled_count = 0;
  bool done = false;
  for (; queued > 0 && !done; ++current) {
    std::vector<int32_t>& bucket = buckets[current & bucket_mask];
    for (std::size_t i = 0; i < bucket.size(); ++i) {
      const int32_t u = bucket[i];
      --queued;
      uint8_t& state = settled[u];
      if (state & kSettledBit) continue;  // a stale entry
      state |= kSettledBit;
      ++settled_count;
      if (stop_early && (state & kTargetBit) && --targets_left == 0) {
        done = true;
        break;
      }
      const float cost_u = cost[u];
      if (from_goal) {
        if (state & kTargetBit) stop_above_cost = 1.25f * cost_u + kFieldMarginCells;
        if (cost_u > stop_above_cost) {
          state &= ~kSettledBit;  // the first cell beyond: left out, as those after it
          --settled_count;
          t.stopped_at_cost_ = cost_u;
          done = true;
          break;
        }
      }
      const float length_u = length[u];
      // Searching from the goal, a step u -> v is the path's step v -> u: it enters u.
      const float m_u = mult[cls[u]];
      bool open[4];
      for (int k = 0; k < 4; ++k) {
        const int32_t v = u + orth[k];
        float m = mult[cls[v]];
        open[k] = m != kInf;
        if (from_goal && open[k]) m = m_u;
        const float candidate = cost_u + m;
        if (candidate < cost[v] && !(field != nullptr && (settled[v] & kSettledBit))) {
          cost[v] = candidate;
          length[v] = length_u + 1.0f;
          parent[v] = u;
          buckets[bucket_of(candidate + heuristic(v))].push_back(v);
          ++queued;
        }
      }
      for (int k = 0; k < 4; ++k) {
        if (!open[diag_sides[k][0]] || !open[diag_sides[k][1]]) continue;
        const int32_t v = u + diag[k];
        const float m = mult[cls[v]];
        const float candidate = cost_u + kSqrt2 * (from_goal && m != kInf ? m_u : m);
        if (candidate < cost[v] && !(field != nullptr && (settled[v] & kSettledBit))) {
          cost[v] = candidate;
          length[v] = length_u + kSqrt2;
          parent[v] = u;
          buckets[bucket_of(candidate + heuristic(v))].push_back(v);
          ++queued;
        }
      }
    }
    bucket.clear();
  }
  t.settled_count_ = settled_count;
}

std::optional<GlobalPath> GlobalPlanner::Plan(const Costmap& costmap, Point2d start_m,
                                              Point2d goal_m, ShortestPathTree* scratch,
                                              const ShortestPathTree* goal_distances) const {
  const CellIndex start = costmap.WorldToCell(start_m);
  const CellIndex goal = costmap.WorldToCell(goal_m);
  if (!costmap.Contains(start) || !costmap.Traversable(goal)) return std::nullopt;
  ShortestPathTree local_tree;
  ShortestPathTree& tree = scratch != nullptr ? *scratch : local_tree;
  SearchImpl(costmap, start, {goal}, goal, &tree, goal_distances);
  return tree.PathTo(goal);
}

std::vector<CellIndex> GoalSnapCandidates(const Costmap& costmap, CellIndex goal, double radius_m) {
  std::vector<CellIndex> candidates;
  const double radius_cells = radius_m / costmap.resolution_m();
  const int reach = static_cast<int>(std::floor(radius_cells));
  for (int dr = -reach; dr <= reach; ++dr) {
    for (int dc = -reach; dc <= reach; ++dc) {
      const CellIndex cell{goal.col + dc, goal.row + dr};
      if (dc * dc + dr * dr > radius_cells * radius_cells || !costmap.Contains(cell) ||
          !costmap.Traversable(cell)) {
        continue;
      }
      const bool sees_goal = VisitLine(
          cell, goal, [&](CellIndex c) { return c == goal || costmap.cost(c) < Costmap::kLethal; });
      if (sees_goal) candidates.push_back(cell);
    }
  }
  return candidates;
}

std::optional<CellIndex> ReachableGoalCell(const ShortestPathTree& tree, CellIndex goal,
                                           const std::vector<CellIndex>& snap_candidates) {
  if (tree.Reachable(goal)) return goal;
  std::optional<CellIndex> best;
  double best_distance2 = 0.0;
  for (const CellIndex& cell : snap_candidates) {
    if (!tree.Reachable(cell)) continue;
    const double distance2 = static_cast<double>((cell.col - goal.col) * (cell.col - goal.col) +
                                                 (cell.row - goal.row) * (cell.row - goal.row));
    if (!best || distance2 < best_distance2 ||
        (distance2 == best_distance2 && tree.CostTo(cell) < tree.CostTo(*best))) {
      best = cell;
      best_distance2 = distance2;
    }
  }
  return best;
}

}  // namespace aslam
