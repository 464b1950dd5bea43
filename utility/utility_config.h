#pragma once

// The utility's options (one struct for the whole aslam-utility component)
// and the loader of the `utility:` config section, validated once at load time.
// Paths are planned as the navigator plans them: the costmap (with the robot's
// radius and clearance margin), the planner options and the goal snap come
// from the navigator's options, so path lengths and reachability are its own.

#include <string>

#include "common/config.h"
#include "navigation/nav_config.h"
#include "utility/exploration_manager.h"
#include "utility/goal_selector.h"

namespace aslam {

struct UtilityOptions {
  GoalSelectorOptions selector;
  // No eligible frontier for this long (message time) and EXPLORE_STATUS says done.
  double done_timeout_s = 10.0;
  // When done, drive back to the exploration's start, then say done (aslam explore --return-home).
  bool return_home = false;
  // ours drives on to a goal whose frontier vanished while its target is reachable, and
  // decides again when the goal ends; fd and ags decide again at once (docs/architecture.md §9).
  bool ours_keeps_vanished_goal = true;
  // ours' selector.pocket_max_area_m2 (goal_selector.h); fd and ags always use 0.
  double ours_pocket_max_area_m2 = 4.0;
  // ours' selector.pocket_near_m; fd and ags defer no pockets.
  double ours_pocket_near_m = 3.0;
  // ours' selector.max_path_length_m: the paper's threshold on lengthy frontier paths;
  // fd and ags always use 0 (no limit).
  double ours_max_path_length_m = 15.0;
};

// The selector's and the manager's options as the configured method uses them: ours' own
// options (ours_*) apply to ours only.
GoalSelectorOptions SelectorOptionsForMethod(const UtilityOptions& options);
ExplorationOptions ExplorationOptionsForMethod(const UtilityOptions& options);

// Reads and validates the `utility` section, planning as `nav` does; throws
// ConfigError naming file, key and value.
UtilityOptions LoadUtilityOptions(const ConfigReader& utility_section, const NavOptions& nav);
// Convenience: the `robot`, `nav` and `utility` sections of `file`; "" gives the defaults.
UtilityOptions LoadUtilityOptionsFromFile(const std::string& file);

}  // namespace aslam
