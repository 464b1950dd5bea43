#include "utility/goal_selector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "utility/unknown_pockets.h"

namespace aslam {
namespace {

constexpr double kMinusInf = -std::numeric_limits<double>::infinity();
constexpr double kTieRelative = 1e-9;

[[noreturn]] void ThrowBadOption(const std::string& name, double value, const std::string& why) {
  std::ostringstream out;
  out << "GoalSelectorOptions." << name << " = " << value << ": " << why;
  throw std::invalid_argument(out.str());
}

double CellDistance(CellIndex a, CellIndex b) {
  return std::hypot(static_cast<double>(a.col - b.col), static_cast<double>(a.row - b.row));
}

bool Within(Point2d a, Point2d b, double radius_m) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m) <= radius_m;
}

bool Blacklisted(Point2d target_m, const std::vector<Point2d>& blacklist_m, double radius_m) {
  return std::any_of(blacklist_m.begin(), blacklist_m.end(),
                     [&](const Point2d& p) { return Within(target_m, p, radius_m); });
}

// a beats b: higher total; near-equal totals go to the shorter path (then the earlier index).
bool Better(const FrontierScore& a, const FrontierScore& b) {
  const double tolerance =
      kTieRelative * std::max(1.0, std::max(std::abs(a.total), std::abs(b.total)));
  if (std::abs(a.total - b.total) > tolerance) return a.total > b.total;
  return a.path_length_m < b.path_length_m;
}

}  // namespace

const char* UtilityMethodName(UtilityMethod method) {
  switch (method) {
    case UtilityMethod::kFd: return "fd";
    case UtilityMethod::kAgs: return "ags";
    case UtilityMethod::kOurs: return "ours";
  }
  return "?";
}

std::optional<UtilityMethod> ParseUtilityMethod(const std::string& name) {
  if (name == "fd") return UtilityMethod::kFd;
  if (name == "ags") return UtilityMethod::kAgs;
  if (name == "ours") return UtilityMethod::kOurs;
  return std::nullopt;
}

const char* EligibilityName(Eligibility eligibility) {
  switch (eligibility) {
    case Eligibility::kEligible: return "eligible";
    case Eligibility::kTooClose: return "too close";
    case Eligibility::kUnreachable: return "unreachable";
    case Eligibility::kBlacklisted: return "blacklisted";
    case Eligibility::kTooFar: return "too far";
    case Eligibility::kPocket: return "pocket";
  }
  return "?";
}

void GoalSelectorOptions::Validate() const {
  path_entropy.Validate();
  if (!(min_distance_m >= 0.0) || !std::isfinite(min_distance_m)) {
    ThrowBadOption("min_distance_m", min_distance_m, "must be finite and >= 0");
  }
  if (!(max_path_length_m >= 0.0) || !std::isfinite(max_path_length_m)) {
    ThrowBadOption("max_path_length_m", max_path_length_m, "must be finite and >= 0 (0: no limit)");
  }
  if (!(blacklist_radius_m >= 0.0) || !std::isfinite(blacklist_radius_m)) {
    ThrowBadOption("blacklist_radius_m", blacklist_radius_m, "must be finite and >= 0");
  }
  if (!(pocket_max_area_m2 >= 0.0) || !std::isfinite(pocket_max_area_m2)) {
    ThrowBadOption("pocket_max_area_m2", pocket_max_area_m2, "must be finite and >= 0 (0: off)");
  }
  if (!(pocket_near_m >= 0.0) || !std::isfinite(pocket_near_m)) {
    ThrowBadOption("pocket_near_m", pocket_near_m,
                   "must be finite and >= 0 (0: every pocket waits)");
  }
  if (!(goal_snap_m >= 0.0) || !std::isfinite(goal_snap_m)) {
    ThrowBadOption("goal_snap_m", goal_snap_m, "must be finite and >= 0");
  }
  costmap.Validate();
  global_planner.Validate();
  ValidateHallucinationOptions(hallucination);
}

bool IsConnected(const WeightedGraph& graph) {
  if (graph.num_nodes <= 0) return false;
  // Union-find over the edges that carry information.
  std::vector<int> parent(graph.num_nodes);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  int components = graph.num_nodes;
  for (const WeightedEdge& e : graph.edges) {
    if (!(e.weight > 0.0) || !std::isfinite(e.weight)) continue;
    if (e.from < 0 || e.to < 0 || e.from >= graph.num_nodes || e.to >= graph.num_nodes) continue;
    const int a = find(e.from);
    const int b = find(e.to);
    if (a != b) {
      parent[a] = b;
      --components;
    }
  }
  return components == 1;
}

GoalSelector::GoalSelector(GoalSelectorOptions options)
    : options_(std::move(options)), planner_(options_.global_planner) {
  options_.Validate();
}

GoalDecision GoalSelector::Decide(const OccupancyGrid& map, const Pose2d& robot,
                                  const PoseGraph& graph, const std::vector<Frontier>& frontiers,
                                  const std::vector<Point2d>& blacklist_m) {
  GoalDecision decision;
  decision.scores.resize(frontiers.size());
  const UtilityMethod method = options_.method;
  costmap_.Update(map, options_.costmap);  // incremental between maps: same costs as a rebuild
  const Costmap& costmap = costmap_;
  const CellIndex robot_cell = map.WorldToCell({robot.x_m, robot.y_m});

  // One search from the robot serves every frontier: wait for every target
  // (or, for one the planner cannot enter, for its snap candidates).
  std::vector<CellIndex> target_cells(frontiers.size());
  std::vector<std::vector<CellIndex>> snap_candidates(frontiers.size());
  std::vector<CellIndex> wait_for;
  for (std::size_t i = 0; i < frontiers.size(); ++i) {
    target_cells[i] = map.WorldToCell(frontiers[i].target_m);
    if (costmap.Contains(target_cells[i]) && costmap.Traversable(target_cells[i])) {
      wait_for.push_back(target_cells[i]);
    } else {
      snap_candidates[i] = GoalSnapCandidates(costmap, target_cells[i], options_.goal_snap_m);
      wait_for.insert(wait_for.end(), snap_candidates[i].begin(), snap_candidates[i].end());
    }
  }
  if (!frontiers.empty()) planner_.Search(costmap, robot_cell, wait_for, &tree_);
  std::vector<double> bordered_unknown_m2(frontiers.size(), 0.0);
  if (options_.pocket_max_area_m2 > 0.0) {
    const Costmap* passable = &costmap;
    if (!options_.costmap.unknown_passable) {
      CostmapOptions unknown_passable = options_.costmap;
      unknown_passable.unknown_passable = true;
      pocket_costmap_.Update(map, unknown_passable);
      passable = &pocket_costmap_;
    }
    bordered_unknown_m2 =
        BorderedUnknownAreasM2(map, *passable, frontiers, options_.pocket_max_area_m2);
  }

  // U1 base: the graph with D-optimality weights, factorized once.
  WeightedGraph base;
  std::unique_ptr<IncrementalLogDet> incremental;
  bool u1_available = false;
  if (MethodUsesGraph(method)) {
    base = ToWeightedGraph(graph);
    decision.graph_nodes = base.num_nodes;
    if (base.num_nodes == 0) {
      decision.note = "empty pose graph: U1 not computed";
    } else if (!IsConnected(base)) {
      decision.note = "pose graph not connected: U1 not computed";
    } else {
      u1_available = true;
      // A 1-node base has an empty reduced Laplacian: nothing to factorize.
      if (base.num_nodes >= 2 && !frontiers.empty()) {
        incremental = std::make_unique<IncrementalLogDet>(base);
      }
    }
  }

  std::vector<std::size_t> near_pockets;
  for (std::size_t i = 0; i < frontiers.size(); ++i) {
    const Frontier& frontier = frontiers[i];
    FrontierScore& s = decision.scores[i];
    s.frontier_id = frontier.id;
    s.target_m = frontier.target_m;
    s.distance_m = CellDistance(robot_cell, target_cells[i]) * map.resolution_m();
    s.bordered_unknown_m2 = bordered_unknown_m2[i];
    s.pocket =
        options_.pocket_max_area_m2 > 0.0 && s.bordered_unknown_m2 < options_.pocket_max_area_m2;

    std::optional<GlobalPath> path;
    // A target the planner can enter but not reach needs its snap candidates only now.
    if (!tree_.Reachable(target_cells[i]) && snap_candidates[i].empty()) {
      snap_candidates[i] = GoalSnapCandidates(costmap, target_cells[i], options_.goal_snap_m);
    }
    if (const auto goal_cell = ReachableGoalCell(tree_, target_cells[i], snap_candidates[i])) {
      path = tree_.PathTo(*goal_cell);
    }
    if (path) s.path_length_m = path->length_m;

    if (s.distance_m < options_.min_distance_m) {
      s.eligibility = Eligibility::kTooClose;
    } else if (!path) {
      s.eligibility = Eligibility::kUnreachable;
    } else if (Blacklisted(frontier.target_m, blacklist_m, options_.blacklist_radius_m)) {
      s.eligibility = Eligibility::kBlacklisted;
    } else if (s.pocket) {
      s.eligibility = Eligibility::kPocket;
      if (s.path_length_m <= options_.pocket_near_m) near_pockets.push_back(i);
    } else if (options_.max_path_length_m > 0.0 && s.path_length_m > options_.max_path_length_m) {
      s.eligibility = Eligibility::kTooFar;
    }

    // Terms are computed for ineligible frontiers too (where a path exists), so
    // that UTILITY_SCORES shows what they would have scored.
    if (u1_available && path) {
      const GraphExtension extension =
          HallucinatePath(graph, path->points_m, map, options_.hallucination);
      s.hallucinated_nodes = extension.num_new_nodes;
      s.hallucinated_edges = static_cast<int>(extension.edges.size());
      const double log_det = incremental ? incremental->LogDet(extension)
                                         : LogDetReducedLaplacianSparse(base, extension);
      s.u1 = U1FromLogDet(log_det, base.num_nodes + extension.num_new_nodes);
    }
    if (method == UtilityMethod::kOurs) {
      const U2Terms u2 = ComputeU2(map, robot_cell, target_cells[i], s.u1, options_.path_entropy);
      s.ray_cells = u2.ray_cells;
      s.path_entropy_bits = u2.path_entropy_bits;
      s.mean_entropy_bits = u2.mean_entropy_bits;
      s.gamma = u2.gamma;
      s.beta = u2.beta;
      s.rho = u2.rho;
      s.u2 = u2.u2;
    }

    s.total = kMinusInf;
    if (s.eligible()) Consider(i, /*nearest_first=*/false, &decision);
  }
  // A pocket this near is cleared now, nearest first, rather than by a trip back at the end:
  // it takes the goal from the method's choice.
  if (!near_pockets.empty()) {
    decision.chosen_index = -1;
    for (const std::size_t i : near_pockets) {
      decision.scores[i].eligibility = Eligibility::kEligible;
      Consider(i, /*nearest_first=*/true, &decision);
    }
  }
  // Neither the length limit nor pockets ever end exploration: frontiers past the limit are
  // chosen from only when no nearer one is eligible, pockets (nearest first) after them.
  for (const Eligibility deferred : {Eligibility::kTooFar, Eligibility::kPocket}) {
    if (decision.num_eligible > 0) break;
    for (std::size_t i = 0; i < frontiers.size(); ++i) {
      if (decision.scores[i].eligibility != deferred) continue;
      decision.scores[i].eligibility = Eligibility::kEligible;
      Consider(i, /*nearest_first=*/deferred == Eligibility::kPocket, &decision);
    }
  }
  if (decision.has_goal()) decision.scores[decision.chosen_index].chosen = true;
  if (incremental) decision.cached_solves = incremental->cached_solves();
  return decision;
}

void GoalSelector::Consider(std::size_t index, bool nearest_first, GoalDecision* decision) const {
  FrontierScore& s = decision->scores[index];
  switch (nearest_first ? UtilityMethod::kFd : options_.method) {
    case UtilityMethod::kFd: s.total = -s.path_length_m; break;
    case UtilityMethod::kAgs: s.total = s.u1; break;
    case UtilityMethod::kOurs: s.total = s.u1 + s.u2; break;
  }
  ++decision->num_eligible;
  if (decision->chosen_index < 0 || Better(s, decision->scores[decision->chosen_index])) {
    decision->chosen_index = static_cast<int>(index);
  }
}

bool GoalSelector::CanReach(const OccupancyGrid& map, const Pose2d& robot, Point2d target_m) {
  costmap_.Update(map, options_.costmap);
  const CellIndex target = map.WorldToCell(target_m);
  std::vector<CellIndex> wait_for;
  if (costmap_.Contains(target) && costmap_.Traversable(target)) wait_for.push_back(target);
  // Snap candidates are needed when the target cannot be entered, or entered but not reached.
  const std::vector<CellIndex> snap_candidates =
      GoalSnapCandidates(costmap_, target, options_.goal_snap_m);
  wait_for.insert(wait_for.end(), snap_candidates.begin(), snap_candidates.end());
  planner_.Search(costmap_, map.WorldToCell({robot.x_m, robot.y_m}), wait_for, &tree_);
  return ReachableGoalCell(tree_, target, snap_candidates).has_value();
}

std::vector<std::size_t> GoalSelector::PointsToRetry(const GoalDecision& decision,
                                                     const std::vector<Point2d>& blacklist_m,
                                                     const std::vector<Point2d>& retried_m) const {
  const double radius_m = options_.blacklist_radius_m;
  std::vector<std::size_t> forgive;
  for (const FrontierScore& score : decision.scores) {
    if (score.eligibility != Eligibility::kBlacklisted) continue;
    std::vector<std::size_t> blocking;
    bool retried_before = false;
    for (std::size_t i = 0; i < blacklist_m.size(); ++i) {
      if (!Within(score.target_m, blacklist_m[i], radius_m)) continue;
      retried_before = retried_before || Blacklisted(blacklist_m[i], retried_m, radius_m);
      blocking.push_back(i);
    }
    if (retried_before) continue;
    forgive.insert(forgive.end(), blocking.begin(), blocking.end());
  }
  std::sort(forgive.begin(), forgive.end());
  forgive.erase(std::unique(forgive.begin(), forgive.end()), forgive.end());
  return forgive;
}

}  // namespace aslam
