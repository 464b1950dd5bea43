#include "eval/bench_settings.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/text_format.h"
#include "drivers/sim/sim_config.h"
#include "frontier/frontier_config.h"
#include "navigation/nav_config.h"
#include "slam/slam_config.h"
#include "utility/utility_config.h"

namespace aslam {
namespace {

namespace fs = std::filesystem;

// The config without its comment lines: what two invocations must agree on.
std::string WithoutComments(const std::string& text) {
  std::istringstream in(text);
  std::string line, body;
  while (std::getline(in, line)) {
    if (line.rfind('#', 0) != 0) body += line + "\n";
  }
  return body;
}

// One --set KEY=V1,V2,... as one override per value.
std::vector<ConfigOverride> ParseSweepArgument(const std::string& argument) {
  const std::size_t equals = argument.find('=');
  const std::vector<std::string> values = equals == std::string::npos
                                              ? std::vector<std::string>{}
                                              : SplitSweepValues(argument.substr(equals + 1));
  // No '=' or no value: the single-value parser says which.
  if (values.empty()) return {ParseConfigOverride(argument)};
  std::vector<ConfigOverride> overrides;
  for (const std::string& value : values) {
    try {
      overrides.push_back(ParseConfigOverride(argument.substr(0, equals + 1) + value));
    } catch (const ConfigError& e) {
      throw ConfigError(std::string(e.what()) + " (in --set '" + argument + "')");
    }
  }
  return overrides;
}

}  // namespace

std::vector<std::string> SplitSweepValues(const std::string& values) {
  std::vector<std::string> result;
  std::string current;
  int depth = 0;
  char quote = 0;
  for (const char c : values) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    } else if (c == ',' && depth == 0) {
      result.push_back(Trim(current));
      current.clear();
      continue;
    }
    current += c;
  }
  result.push_back(Trim(current));
  if (result.size() == 1 && result[0].empty()) result.clear();
  return result;
}

void CheckRunOverride(const ConfigOverride& override_) {
  const std::string where = "--set '" + override_.Key() + "=" + override_.value + "': ";
  const std::string key = override_.Key();
  if (key == "utility.method")
    throw std::invalid_argument(where + "the method is --method (bench: --methods)");
  if (key == "sim.seed") throw std::invalid_argument(where + "the seed is --seed (bench: --seeds)");
  static const std::vector<std::string> kRead = {"robot",    "sim",     "slam",
                                                 "frontier", "utility", "nav"};
  if (std::find(kRead.begin(), kRead.end(), override_.path[0]) == kRead.end()) {
    throw std::invalid_argument(where + "no explore component reads a section '" +
                                override_.path[0] + "' (robot, sim, slam, frontier, utility, nav)");
  }
}

std::string SettingLabel(const std::vector<ConfigOverride>& overrides) {
  std::string label;
  for (const ConfigOverride& o : overrides) {
    std::string value = o.value;
    for (char& c : value) {
      if (c == '/' || std::isspace(static_cast<unsigned char>(c))) c = '_';
    }
    if (!label.empty()) label += kSettingSeparator;
    label += o.Key() + "=" + value;
  }
  return label;
}

std::vector<BenchSetting> PlanSettings(const std::vector<std::string>& sweep) {
  std::vector<std::vector<ConfigOverride>> axes;
  std::set<std::string> keys;
  for (const std::string& argument : sweep) {
    try {
      axes.push_back(ParseSweepArgument(argument));
    } catch (const ConfigError& e) {
      throw std::invalid_argument(e.what());
    }
    for (const ConfigOverride& o : axes.back()) CheckRunOverride(o);
    if (!keys.insert(axes.back()[0].Key()).second)
      throw std::invalid_argument("--set " + axes.back()[0].Key() + " is given twice");
  }
  // The cartesian product, the last axis varying fastest.
  std::vector<std::vector<ConfigOverride>> grid = {{}};
  for (const std::vector<ConfigOverride>& axis : axes) {
    std::vector<std::vector<ConfigOverride>> next;
    for (const std::vector<ConfigOverride>& partial : grid) {
      for (const ConfigOverride& value : axis) {
        next.push_back(partial);
        next.back().push_back(value);
      }
    }
    grid = std::move(next);
  }
  std::vector<BenchSetting> settings;
  std::set<std::string> labels;
  for (std::vector<ConfigOverride>& overrides : grid) {
    const std::string label = SettingLabel(overrides);
    if (!labels.insert(label).second)
      throw std::invalid_argument("--set: two settings are labelled '" + label + "'");
    if (label.size() > 255)
      throw std::invalid_argument("--set: the label '" + label + "' is too long for a folder name");
    settings.push_back({label, std::move(overrides)});
  }
  return settings;
}

std::string SettingConfigPath(const std::string& out_dir, const std::string& label) {
  return out_dir + "/settings/" + label + "/config.yaml";
}

void WriteSettingConfigs(const std::string& config_file, const std::vector<BenchSetting>& settings,
                         const std::string& out_dir) {
  for (const BenchSetting& setting : settings) {
    if (setting.label.empty()) continue;
    std::string text = "# written by aslam bench: " +
                       (config_file.empty() ? std::string("built-in defaults") : config_file);
    for (const ConfigOverride& o : setting.overrides) text += " --set " + o.Key() + "=" + o.value;
    text += "\n" + ApplyConfigOverrides(config_file, setting.overrides);
    const std::string path = SettingConfigPath(out_dir, setting.label);
    // Runs of a setting must share its config: a resumed bench may not change it under them.
    if (fs::exists(path) && WithoutComments(ReadTextFile(path)) != WithoutComments(text) &&
        fs::exists(out_dir + "/runs/" + setting.label)) {
      throw std::runtime_error(path + " differs from this invocation's config for " +
                               setting.label + " (was --config changed?) and " + out_dir +
                               "/runs/" + setting.label +
                               " holds its runs: they would mix; use another --out, or remove "
                               "both");
    }
    fs::create_directories(fs::path(path).parent_path());
    WriteFileAtomically(path, text);
  }
  // Loaded as `aslam explore` loads it, before any run starts (docs/architecture.md §7).
  for (const BenchSetting& setting : settings) {
    if (setting.label.empty()) continue;
    const std::string path = SettingConfigPath(out_dir, setting.label);
    (void)LoadSimulatorOptionsFromFile(path);
    (void)LoadSlamConfigFromFile(path);
    (void)LoadFrontierOptionsFromFile(path);
    (void)LoadUtilityOptionsFromFile(path);
    (void)LoadNavOptionsFromFile(path);
  }
}

}  // namespace aslam
