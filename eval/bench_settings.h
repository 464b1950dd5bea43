#pragma once

// `aslam bench --set KEY=V1,V2 [--set KEY2=...]`: the grid of config settings a bench sweeps.
// A setting takes one value of every --set: the grid is their cartesian product, the first
// --set varying slowest. Its label, e.g. "utility.lambda=0.3+nav.goal_snap_m=0.1" (key=value
// pairs in --set order joined by '+'), names its folders: OUT/runs/<label>/<world>/<method>/
// seed_NN/ and OUT/settings/<label>/, whose config.yaml (the bench's --config with the
// setting's overrides) every run of the setting reads.

#include <string>
#include <vector>

#include "common/config.h"

namespace aslam {

// Joins a label's key=value pairs: legal in a folder name and needs no shell quoting.
inline constexpr char kSettingSeparator = '+';

struct BenchSetting {
  std::string label;                      // "" for the one setting of a bench without --set
  std::vector<ConfigOverride> overrides;  // one per --set, in the order given
};

// "0.3, 0.6,[1, 2]" -> {"0.3", "0.6", "[1, 2]"}: split at commas outside brackets, braces and
// quotes, each value trimmed.
std::vector<std::string> SplitSweepValues(const std::string& values);

// Throws std::invalid_argument naming the --set for a key that an explore run does not take
// from its config: utility.method (--method), sim.seed (--seed), or a section no explore
// component reads (anything but robot, sim, slam, frontier, utility, nav).
void CheckRunOverride(const ConfigOverride& override_);

// The key=value pairs joined by kSettingSeparator; '/' and whitespace in a value become '_'
// so the label is one folder name.
std::string SettingLabel(const std::vector<ConfigOverride>& overrides);

// The grid of `sweep` (the --set arguments in the order given); one unlabelled setting when
// `sweep` is empty. Throws std::invalid_argument naming the --set for bad syntax, an empty
// value list, a key given twice, a key CheckRunOverride refuses, or two settings with the same
// label.
std::vector<BenchSetting> PlanSettings(const std::vector<std::string>& sweep);

// OUT/settings/<label>/config.yaml.
std::string SettingConfigPath(const std::string& out_dir, const std::string& label);

// Writes each labelled setting's config (`config_file`, "" = defaults, with its overrides) to
// SettingConfigPath and loads it as every explore component does, so a misspelt key fails
// before any run starts. Throws ConfigError naming the file and key, or std::runtime_error when
// an earlier invocation's config differs and the setting has runs (the base config changed:
// old and new runs would mix).
void WriteSettingConfigs(const std::string& config_file, const std::vector<BenchSetting>& settings,
                         const std::string& out_dir);

}  // namespace aslam
