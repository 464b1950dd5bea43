#pragma once

// One goal decision (docs/architecture.md §5, issue #5): every frontier is scored by the
// configured method and the best eligible one wins. No LCM, no wall clock.
//
//   eligibility  ineligible (total = -inf) when the target is closer than
//                min_distance_m to the robot, unreachable in the costmap,
//                within blacklist_radius_m of a reached or failed goal, or its
//                planned path is longer than max_path_length_m (0: no limit) while
//                a frontier nearer than that is eligible
//   pockets      with pocket_max_area_m2 > 0 (ours), a frontier whose unknown is an
//                enclosed pocket smaller than that (unknown_pockets.h) is chosen from
//                only when nothing else is eligible, and then nearest first; one whose
//                path is at most pocket_near_m is chosen first (nearest first)
//   fd           total = -path length: the nearest eligible frontier by path
//   ags          total = U1 (spanning trees of the graph extended by the
//                hallucinated path to the frontier)
//   ours         total = U1 + U2 (path_entropy.h)
//
// Path lengths and paths come from ONE one-to-all Dijkstra from the robot; U1
// from one factorization of the current graph (IncrementalLogDet) plus one
// LogDet per frontier. Terms a method does not use are left 0. Ties (within
// 1e-9 relative) go to the shorter path, then to the earlier frontier.

#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"
#include "common/pose2d.h"
#include "common/pose_graph.h"
#include "frontier/frontier.h"
#include "navigation/costmap.h"
#include "navigation/global_planner.h"
#include "utility/hallucination.h"
#include "utility/path_entropy.h"
#include "utility/spanning_trees.h"

namespace aslam {

enum class UtilityMethod { kFd, kAgs, kOurs };

// "fd", "ags", "ours".
const char* UtilityMethodName(UtilityMethod method);
std::optional<UtilityMethod> ParseUtilityMethod(const std::string& name);
// ags and ours score the pose graph; fd does not need one.
inline bool MethodUsesGraph(UtilityMethod method) { return method != UtilityMethod::kFd; }

// Codes equal frontier_score_t's ELIGIBLE / INELIGIBLE_* constants.
enum class Eligibility {
  kEligible = 0,
  kTooClose = 1,
  kUnreachable = 2,
  kBlacklisted = 3,
  kTooFar = 4,
  kPocket = 5
};
const char* EligibilityName(Eligibility eligibility);

struct GoalSelectorOptions {
  UtilityMethod method = UtilityMethod::kOurs;
  PathEntropyOptions path_entropy;  // λ and the unit of d in γ
  double min_distance_m =
      0.25;  // targets closer to the robot are ineligible (docs/architecture.md §5)
  // Longer planned paths are ineligible while a shorter one is eligible; 0 = no limit.
  double max_path_length_m = 0.0;
  double blacklist_radius_m = 0.5;  // targets this close to a reached/failed goal are ineligible
  // Frontiers onto an enclosed unknown pocket smaller than this wait until nothing else is
  // eligible, then go nearest first; 0 = off (what fd and ags always use).
  double pocket_max_area_m2 = 0.0;
  // A pocket whose planned path is at most this long is not deferred but chosen at once,
  // nearest first, over the open frontiers: the robot clears a room's pockets while it is
  // there instead of driving back at the end (0: every pocket waits).
  double pocket_near_m = 0.0;
  // A target the planner cannot enter (e.g. in the inflated zone) is planned
  // to the reachable cell nearest to it within this distance, as the navigator does.
  double goal_snap_m = 0.5;
  CostmapOptions costmap;  // the planning costmap (same defaults as the navigator's)
  GlobalPlannerOptions global_planner;
  HallucinationOptions hallucination;

  // Throws std::invalid_argument naming the field and value.
  void Validate() const;
};

// Every term for one frontier (what UTILITY_SCORES carries).
struct FrontierScore {
  int frontier_id = -1;
  Point2d target_m;             // the frontier's target, "map"
  double path_length_m = -1.0;  // planned path robot -> target; -1 if unreachable
  double distance_m = 0.0;      // Euclidean robot cell -> target cell centres
  int ray_cells = 0;            // K
  double path_entropy_bits = 0.0;
  double mean_entropy_bits = 0.0;
  double gamma = 0.0;
  int beta = 0;
  double rho = 0.0;
  double u1 = 0.0;
  double u2 = 0.0;
  double total = 0.0;  // -inf when ineligible
  // The enclosed unknown the frontier borders (unknown_pockets.h); +inf: open. 0 when
  // pocket_max_area_m2 is 0.
  double bordered_unknown_m2 = 0.0;
  // Borders a pocket (bordered_unknown_m2 < pocket_max_area_m2): deferred, or scored
  // nearest first when only pockets are left.
  bool pocket = false;
  Eligibility eligibility = Eligibility::kEligible;
  bool chosen = false;
  // Diagnostics of the hallucinated extension (ags, ours).
  int hallucinated_nodes = 0;
  int hallucinated_edges = 0;
  bool eligible() const { return eligibility == Eligibility::kEligible; }
};

struct GoalDecision {
  std::vector<FrontierScore> scores;  // one per input frontier, in input order
  int chosen_index = -1;              // into scores; -1 when nothing is eligible
  int num_eligible = 0;
  int graph_nodes = 0;    // size of the pose graph scored (0 for fd)
  int cached_solves = 0;  // IncrementalLogDet solves (diagnostic)
  std::string note;       // why U1 could not be computed, if so
  bool has_goal() const { return chosen_index >= 0; }
  const FrontierScore& chosen() const { return scores[chosen_index]; }
};

// True when every node is reachable from node 0 over edges of positive finite
// weight, i.e. the reduced Laplacian is positive definite (true for 1 node).
bool IsConnected(const WeightedGraph& graph);

class GoalSelector {
 public:
  // Throws std::invalid_argument for invalid options.
  explicit GoalSelector(GoalSelectorOptions options);

  // Scores `frontiers` from `robot` on `map`. `graph` is scored by ags and ours
  // (ignored by fd); an empty or disconnected graph leaves every U1 at 0 and
  // says so in `note`. `blacklist_m` holds reached and failed goal targets.
  GoalDecision Decide(const OccupancyGrid& map, const Pose2d& robot, const PoseGraph& graph,
                      const std::vector<Frontier>& frontiers,
                      const std::vector<Point2d>& blacklist_m);

  // Whether the robot can reach `target_m` on `map` (snapped as Decide and the navigator do).
  bool CanReach(const OccupancyGrid& map, const Pose2d& robot, Point2d target_m);

  // The last pass before nothing is eligible: the blacklist points (indices into `blacklist_m`)
  // to forgive so that the reachable frontiers `decision` found blacklisted are tried once
  // more. A point within blacklist_radius_m of one in `retried_m` (forgiven before) is not
  // forgiven again, and a frontier such a point still blocks is left out.
  std::vector<std::size_t> PointsToRetry(const GoalDecision& decision,
                                         const std::vector<Point2d>& blacklist_m,
                                         const std::vector<Point2d>& retried_m) const;

  const GoalSelectorOptions& options() const { return options_; }

 private:
  // Gives an eligible score its method's total (or, `nearest_first`, fd's) and chooses it
  // if it beats the chosen one.
  void Consider(std::size_t index, bool nearest_first, GoalDecision* decision) const;

  GoalSelectorOptions options_;
  GlobalPlanner planner_;
  // Reused across decisions: no allocation per decision on a same-size map.
  Costmap costmap_;
  // Pockets are measured where the robot could be once the unknown is known: with
  // costmap.unknown_passable false, on this copy of costmap_ with it true.
  Costmap pocket_costmap_;
  ShortestPathTree tree_;
};

}  // namespace aslam
