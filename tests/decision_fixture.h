#pragma once

// The utility options logs/decision_fixture.lcmlog is recorded (tests/record_fixture.cc) and
// replayed (tests/utility_replay_test.cc) with.

#include <string>

#include "common/config.h"
#include "navigation/nav_config.h"
#include "utility/utility_config.h"

namespace aslam {

inline UtilityOptions DecisionFixtureUtilityOptions(const std::string& config,
                                                    const NavOptions& nav) {
  UtilityOptions options = LoadUtilityOptions(ConfigReader::FromFile(config, "utility"), nav);
  // The fixture's robot follows a scripted drive with no navigator, so no goal is ever reached:
  // ours decides again whenever its goal's frontier vanishes, as fd and ags do, or it would
  // make one decision only.
  options.ours_keeps_vanished_goal = false;
  return options;
}

}  // namespace aslam
