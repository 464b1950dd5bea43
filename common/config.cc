#include "common/config.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace aslam {
namespace {

std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "null";
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  YAML::Emitter emitter;
  emitter << YAML::Flow << node;
  return emitter.c_str();
}

std::string LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? ":" + std::to_string(mark.line + 1) : "";
}

YAML::Node ParseFile(const std::string& file) {
  try {
    return YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw ConfigError(file + ": cannot open config file");
  } catch (const YAML::ParserException& e) {
    throw ConfigError(file + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
}

YAML::Node ParseString(const std::string& text, const std::string& origin) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(origin + ":" + std::to_string(e.mark.line + 1) +
                      ": malformed YAML: " + e.msg);
  }
}

}  // namespace

const std::vector<std::string>& KnownConfigSections() {
  static const std::vector<std::string> sections = {"robot",   "sim",     "slam",    "frontier",
                                                    "utility", "nav",     "procman", "explore",
                                                    "eval",    "rplidar", "hokuyo",  "kobuki"};
  return sections;
}

ConfigReader::ConfigReader(YAML::Node node, std::string file, std::string path,
                           std::shared_ptr<std::set<std::string>> used)
    : node_(std::move(node)),
      file_(std::move(file)),
      path_(std::move(path)),
      used_paths_(std::move(used)) {}

ConfigReader ConfigReader::FromRoot(YAML::Node root, const std::string& section,
                                    const std::string& origin) {
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(origin + ": expected a mapping of sections at top level");
  const auto& known = KnownConfigSections();
  for (const auto& entry : root) {
    const std::string name = entry.first.as<std::string>();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      throw ConfigError(origin + LineOf(entry.first) + ": unknown section '" + name + "'");
    }
  }
  const YAML::Node value = root[section];
  const YAML::Node node =
      (!value.IsDefined() || value.IsNull()) ? YAML::Node(YAML::NodeType::Map) : value;
  if (!node.IsMap()) {
    throw ConfigError(origin + LineOf(node) + ": section '" + section +
                      "' must be a mapping, got " + Describe(node));
  }
  return ConfigReader(node, origin, section, std::make_shared<std::set<std::string>>());
}

ConfigReader ConfigReader::FromString(const std::string& yaml_text, const std::string& section,
                                      const std::string& origin) {
  return FromRoot(ParseString(yaml_text, origin), section, origin);
}

ConfigReader ConfigReader::FromFile(const std::string& file, const std::string& section) {
  return FromRoot(ParseFile(file), section, file);
}

ConfigReader ConfigReader::FromOptionalFile(const std::string& file, const std::string& section) {
  if (file.empty()) return FromRoot(YAML::Node(YAML::NodeType::Map), section, "<defaults>");
  return FromFile(file, section);
}

ConfigReader ConfigReader::WholeFile(const std::string& file) {
  YAML::Node root = ParseFile(file);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(file + ": expected a mapping at top level");
  return ConfigReader(root, file, "", std::make_shared<std::set<std::string>>());
}

std::string ConfigReader::KeyPath(const std::string& key) const { return Join(path_, key); }

YAML::Node ConfigReader::Get(const std::string& key) const {
  used_paths_->insert(KeyPath(key));
  return node_[key];
}

bool ConfigReader::Has(const std::string& key) const { return node_[key].IsDefined(); }

std::string ConfigReader::ValueText(const std::string& key) const { return Describe(node_[key]); }

void ConfigReader::Fail(const std::string& key, const std::string& problem) const {
  const YAML::Node value = node_[key];
  const std::string where = value.IsDefined() ? LineOf(value) : "";
  throw ConfigError(file_ + where + ": " + KeyPath(key) + " = " + Describe(value) + ": " + problem);
}

template <typename T>
void ConfigReader::ReadScalar(const std::string& key, T* value, const char* expected) const {
  const YAML::Node node = Get(key);
  if (!node.IsDefined()) return;
  if (!node.IsScalar()) Fail(key, std::string("expected ") + expected);
  try {
    *value = node.as<T>();
  } catch (const YAML::Exception&) {
    Fail(key, std::string("expected ") + expected);
  }
}

void ConfigReader::Read(const std::string& key, double* value) const {
  ReadScalar(key, value, "a number");
  if (Has(key) && !std::isfinite(*value)) Fail(key, "expected a finite number");
}
void ConfigReader::Read(const std::string& key, int* value) const {
  ReadScalar(key, value, "an integer");
}
void ConfigReader::Read(const std::string& key, int64_t* value) const {
  ReadScalar(key, value, "an integer");
}
void ConfigReader::Read(const std::string& key, uint64_t* value) const {
  const YAML::Node node = node_[key];
  if (node.IsDefined() && node.IsScalar() && !node.Scalar().empty() && node.Scalar()[0] == '-') {
    Get(key);
    Fail(key, "expected a non-negative integer");
  }
  ReadScalar(key, value, "a non-negative integer");
}
void ConfigReader::Read(const std::string& key, bool* value) const {
  ReadScalar(key, value, "true or false");
}
void ConfigReader::Read(const std::string& key, std::string* value) const {
  ReadScalar(key, value, "a string");
}
void ConfigReader::Read(const std::string& key, std::vector<double>* value) const {
  const YAML::Node node = Get(key);
  if (!node.IsDefined()) return;
  if (!node.IsSequence()) Fail(key, "expected a list of numbers");
  std::vector<double> result;
  for (const auto& item : node) {
    try {
      result.push_back(item.as<double>());
    } catch (const YAML::Exception&) {
      Fail(key, "expected a list of numbers");
    }
    if (!std::isfinite(result.back())) Fail(key, "expected finite numbers");
  }
  *value = std::move(result);
}

void ConfigReader::ReadInRange(const std::string& key, double* value, double min,
                               double max) const {
  Read(key, value);
  if (!(*value >= min && *value <= max)) {
    std::ostringstream problem;
    problem << "must be in [" << min << ", " << max << "]";
    Fail(key, problem.str());
  }
}

void ConfigReader::ReadInRange(const std::string& key, int* value, int min, int max) const {
  Read(key, value);
  if (*value < min || *value > max) {
    Fail(key, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  }
}

void ConfigReader::ReadPositive(const std::string& key, double* value) const {
  Read(key, value);
  if (!(*value > 0.0)) Fail(key, "must be positive");
}

ConfigReader ConfigReader::Section(const std::string& key) const {
  const YAML::Node value = Get(key);
  // A missing key yields an invalid node that must not be assigned to.
  const YAML::Node node =
      (!value.IsDefined() || value.IsNull()) ? YAML::Node(YAML::NodeType::Map) : value;
  if (!node.IsMap()) Fail(key, "expected a mapping");
  return ConfigReader(node, file_, KeyPath(key), used_paths_);
}

std::vector<ConfigReader> ConfigReader::List(const std::string& key) const {
  const YAML::Node node = Get(key);
  std::vector<ConfigReader> items;
  if (!node.IsDefined() || node.IsNull()) return items;
  if (!node.IsSequence()) Fail(key, "expected a list");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string item_path = KeyPath(key) + "[" + std::to_string(i) + "]";
    if (!node[i].IsMap()) {
      throw ConfigError(file_ + LineOf(node[i]) + ": " + item_path + " = " + Describe(node[i]) +
                        ": expected a mapping");
    }
    used_paths_->insert(item_path);
    items.push_back(ConfigReader(node[i], file_, item_path, used_paths_));
  }
  return items;
}

void ConfigReader::CheckAllKeysUsed() const {
  // Walks this reader's subtree; a key counts as used if it or a parent was read as a leaf.
  struct Walker {
    const ConfigReader& reader;
    void Walk(const YAML::Node& node, const std::string& path) const {
      if (node.IsMap()) {
        for (const auto& entry : node) {
          const std::string key = entry.first.as<std::string>();
          const std::string key_path = Join(path, key);
          if (!reader.used_paths_->count(key_path)) {
            throw ConfigError(reader.file_ + LineOf(entry.first) + ": " + key_path +
                              ": unknown key");
          }
          if (entry.second.IsMap() || entry.second.IsSequence()) Walk(entry.second, key_path);
        }
      } else if (node.IsSequence()) {
        for (std::size_t i = 0; i < node.size(); ++i) {
          const std::string item_path = path + "[" + std::to_string(i) + "]";
          if (reader.used_paths_->count(item_path)) Walk(node[i], item_path);
        }
      }
    }
  };
  Walker{*this}.Walk(node_, path_);
}

std::string ConfigOverride::Key() const {
  std::string key;
  for (const std::string& part : path) key = Join(key, part);
  return key;
}

ConfigOverride ParseConfigOverride(const std::string& argument) {
  const std::string where = "--set '" + argument + "': ";
  const std::size_t equals = argument.find('=');
  if (equals == std::string::npos) throw ConfigError(where + "expected KEY=VALUE");
  ConfigOverride result;
  const std::string key = argument.substr(0, equals);
  if (key.empty()) throw ConfigError(where + "empty key before '='");
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = key.find('.', begin);
    result.path.push_back(key.substr(begin, dot - begin));
    if (result.path.back().empty()) throw ConfigError(where + "empty part in key '" + key + "'");
    if (dot == std::string::npos) break;
    begin = dot + 1;
  }
  result.value = argument.substr(equals + 1);
  if (result.value.find_first_not_of(" \t") == std::string::npos) {
    throw ConfigError(where + "empty value after '=' (write \"\" for an empty string)");
  }
  YAML::Node value;
  try {
    value = YAML::Load(result.value);
  } catch (const YAML::Exception& e) {
    throw ConfigError(where + "malformed YAML value: " + e.msg);
  }
  if (value.IsMap()) throw ConfigError(where + "expected a scalar or a [flow, sequence]");
  return result;
}

std::string ApplyConfigOverrides(const std::string& config_file,
                                 const std::vector<ConfigOverride>& overrides) {
  const std::string origin = config_file.empty() ? "<defaults>" : config_file;
  YAML::Node root = config_file.empty() ? YAML::Node(YAML::NodeType::Map) : ParseFile(config_file);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(origin + ": expected a mapping of sections at top level");
  for (const ConfigOverride& override_ : overrides) {
    // yaml-cpp nodes are references: reset() rebinds, assignment would overwrite the value.
    YAML::Node node = root;
    std::string prefix;
    for (std::size_t i = 0; i + 1 < override_.path.size(); ++i) {
      prefix = Join(prefix, override_.path[i]);
      YAML::Node child = node[override_.path[i]];
      if (!child.IsDefined() || child.IsNull()) {
        child = YAML::Node(YAML::NodeType::Map);
      } else if (!child.IsMap()) {
        throw ConfigError("--set '" + override_.Key() + "=" + override_.value + "': " + origin +
                          LineOf(child) + ": " + prefix + " = " + Describe(child) +
                          " is not a mapping");
      }
      node.reset(child);
    }
    node[override_.path.back()] = YAML::Load(override_.value);
  }
  YAML::Emitter emitter;
  emitter << root;
  return std::string(emitter.c_str()) + "\n";
}

}  // namespace aslam
