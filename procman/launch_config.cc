#include "procman/launch_config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <stdexcept>

namespace aslam {
namespace {

const std::set<std::string> kTopKeys = {"deputy", "stop_timeout_s", "processes"};
const std::set<std::string> kProcessKeys = {"name",    "command",     "args",       "env",
                                            "group",   "start_order", "auto_start", "start_delay_s",
                                            "restart", "backoff"};
const std::set<std::string> kBackoffKeys = {"initial_s", "max_s", "factor", "reset_after_s",
                                            "give_up_after_failures"};

// ConfigReader has no list-of-strings or free-form map reader, so the raw node
// answers which keys exist; every value still goes through the reader for its errors.
void CheckKnownKeys(const ConfigReader& reader, const YAML::Node& raw,
                    const std::set<std::string>& known) {
  if (!raw.IsDefined() || !raw.IsMap()) return;
  for (const auto& entry : raw) {
    const std::string key = entry.first.as<std::string>();
    if (!known.count(key)) reader.Fail(key, "unknown key");
  }
}

// Names become file names (LOG_DIR/NAME.log) and command-line arguments.
bool IsPlainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
         });
}

std::string Substitute(const ConfigReader& reader, const std::string& key, const std::string& text,
                       const LaunchVariables& variables) {
  try {
    return SubstituteVariables(text, variables);
  } catch (const std::invalid_argument& e) {
    reader.Fail(key, e.what());
  }
}

RestartPolicy ParseRestart(const ConfigReader& reader) {
  std::string text = "never";
  reader.Read("restart", &text);
  if (text == "never") return RestartPolicy::kNever;
  if (text == "on-failure") return RestartPolicy::kOnFailure;
  if (text == "always") return RestartPolicy::kAlways;
  reader.Fail("restart", "unknown restart policy; expected never, on-failure or always");
}

BackoffOptions LoadBackoff(const ConfigReader& process, const YAML::Node& raw) {
  BackoffOptions b;
  const ConfigReader r = process.Section("backoff");
  CheckKnownKeys(r, raw, kBackoffKeys);
  r.ReadInRange("initial_s", &b.initial_s, 0.0, 3600.0);
  r.ReadInRange("max_s", &b.max_s, 0.0, 86400.0);
  r.ReadInRange("factor", &b.factor, 1.0, 100.0);
  r.ReadInRange("reset_after_s", &b.reset_after_s, 0.0, 86400.0);
  r.ReadInRange("give_up_after_failures", &b.give_up_after_failures, 0, 1000000);
  if (b.max_s < b.initial_s) r.Fail("max_s", "must not be below initial_s");
  return b;
}

ProcessConfig LoadProcess(const ConfigReader& r, const YAML::Node& raw,
                          const LaunchVariables& variables) {
  CheckKnownKeys(r, raw, kProcessKeys);
  ProcessConfig p;
  r.Read("name", &p.name);
  if (!IsPlainName(p.name)) r.Fail("name", "required; letters, digits, '_', '-' and '.' only");
  r.Read("command", &p.command);
  if (p.command.empty()) r.Fail("command", "required");
  p.command = Substitute(r, "command", p.command, variables);

  const YAML::Node args = raw["args"];
  if (args.IsDefined() && !args.IsNull()) {
    if (!args.IsSequence()) r.Fail("args", "expected a list of strings");
    for (const auto& item : args) {
      if (!item.IsScalar()) r.Fail("args", "expected a list of strings");
      p.args.push_back(Substitute(r, "args", item.Scalar(), variables));
    }
  }
  r.Section("env");  // checks it is a mapping
  const YAML::Node env = raw["env"];
  if (env.IsDefined() && env.IsMap()) {
    const ConfigReader e = r.Section("env");
    for (const auto& entry : env) {
      const std::string key = entry.first.as<std::string>();
      if (key.empty() || key.find('=') != std::string::npos) e.Fail(key, "bad variable name");
      std::string value;
      e.Read(key, &value);
      p.env[key] = Substitute(e, key, value, variables);
    }
  }
  r.Read("group", &p.group);
  if (!p.group.empty() && !IsPlainName(p.group)) {
    r.Fail("group", "letters, digits, '_', '-' and '.' only");
  }
  r.ReadInRange("start_order", &p.start_order, -1000000, 1000000);
  r.Read("auto_start", &p.auto_start);
  r.ReadInRange("start_delay_s", &p.start_delay_s, 0.0, 3600.0);
  p.restart = ParseRestart(r);
  p.backoff = LoadBackoff(r, raw["backoff"]);
  return p;
}

LaunchConfig Load(const ConfigReader& top, const YAML::Node& raw_root,
                  const LaunchVariables& variables) {
  const YAML::Node raw = raw_root.IsMap() ? raw_root["procman"] : YAML::Node();
  CheckKnownKeys(top, raw, kTopKeys);
  LaunchConfig config;
  top.Read("deputy", &config.deputy);
  if (!IsPlainName(config.deputy)) top.Fail("deputy", "letters, digits, '_', '-' and '.' only");
  top.ReadInRange("stop_timeout_s", &config.stop_timeout_s, 0.0, 3600.0);
  const std::vector<ConfigReader> items = top.List("processes");
  if (items.empty()) top.Fail("processes", "expected a non-empty list of processes");
  std::set<std::string> names;
  for (std::size_t i = 0; i < items.size(); ++i) {
    ProcessConfig p = LoadProcess(items[i], raw["processes"][i], variables);
    if (!names.insert(p.name).second) items[i].Fail("name", "duplicate process name");
    config.processes.push_back(std::move(p));
  }
  return config;
}

}  // namespace

const char* RestartPolicyName(RestartPolicy policy) {
  switch (policy) {
    case RestartPolicy::kNever: return "never";
    case RestartPolicy::kOnFailure: return "on-failure";
    case RestartPolicy::kAlways: return "always";
  }
  return "?";
}

double BackoffDelayS(const BackoffOptions& backoff, int consecutive_failures) {
  const int exponent = std::max(0, consecutive_failures - 1);
  // Computed in log space so a long failure streak cannot overflow.
  const double log_delay =
      std::log(std::max(backoff.initial_s, 1e-9)) + exponent * std::log(backoff.factor);
  if (backoff.initial_s <= 0.0) return 0.0;
  return std::min(backoff.max_s, std::exp(std::min(log_delay, 700.0)));
}

std::string SubstituteVariables(const std::string& text, const LaunchVariables& variables) {
  std::string result;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t start = text.find("${", pos);
    if (start == std::string::npos) {
      result.append(text, pos, std::string::npos);
      break;
    }
    result.append(text, pos, start - pos);
    const std::size_t end = text.find('}', start);
    if (end == std::string::npos) throw std::invalid_argument("unterminated ${ in '" + text + "'");
    const std::string name = text.substr(start + 2, end - start - 2);
    const auto found = variables.find(name);
    if (found == variables.end()) {
      std::string known;
      for (const auto& [key, value] : variables) known += (known.empty() ? "" : ", ") + key;
      throw std::invalid_argument("unknown variable ${" + name +
                                  "}; known: " + (known.empty() ? "none" : known));
    }
    result += found->second;
    pos = end + 1;
  }
  return result;
}

LaunchConfig LoadLaunchConfigFromFile(const std::string& file, const LaunchVariables& variables) {
  const ConfigReader top = ConfigReader::FromFile(file, "procman");  // checks file and sections
  return Load(top, YAML::LoadFile(file), variables);
}

LaunchConfig LoadLaunchConfigFromString(const std::string& yaml_text,
                                        const LaunchVariables& variables,
                                        const std::string& origin) {
  const ConfigReader top = ConfigReader::FromString(yaml_text, "procman", origin);
  return Load(top, YAML::Load(yaml_text), variables);
}

}  // namespace aslam
