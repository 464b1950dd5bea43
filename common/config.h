#pragma once

// YAML config loading: each component reads its section into its own
// options struct once, at load time. Unknown keys, wrong types and
// out-of-range values throw ConfigError naming the file, the key and the value.

#include <cstdint>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace aslam {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Top-level sections a config file may hold; anything else is a typo.
const std::vector<std::string>& KnownConfigSections();

// One YAML mapping being read into an options struct. Every key read is
// recorded, so CheckAllKeysUsed() catches misspelt or unsupported keys.
class ConfigReader {
 public:
  // Loads `file` and takes its top-level mapping `section`; a missing
  // section reads as empty (all defaults). Throws ConfigError on a missing or
  // malformed file or an unknown top-level section.
  static ConfigReader FromFile(const std::string& file, const std::string& section);
  // FromFile, except that no file ("") reads as an empty section (all defaults).
  static ConfigReader FromOptionalFile(const std::string& file, const std::string& section);
  // The same for YAML text; `origin` names it in error messages.
  static ConfigReader FromString(const std::string& yaml_text, const std::string& section,
                                 const std::string& origin = "<string>");
  // A reader over a whole document (no section), e.g. a drive file.
  static ConfigReader WholeFile(const std::string& file);

  // Optional keys: `*value` keeps its default when the key is absent.
  void Read(const std::string& key, double* value) const;
  void Read(const std::string& key, int* value) const;
  void Read(const std::string& key, int64_t* value) const;
  void Read(const std::string& key, uint64_t* value) const;
  void Read(const std::string& key, bool* value) const;
  void Read(const std::string& key, std::string* value) const;
  void Read(const std::string& key, std::vector<double>* value) const;

  // Reads and checks min <= value <= max (inclusive).
  void ReadInRange(const std::string& key, double* value, double min, double max) const;
  void ReadInRange(const std::string& key, int* value, int min, int max) const;
  // Reads and checks value > 0.
  void ReadPositive(const std::string& key, double* value) const;

  bool Has(const std::string& key) const;
  // A nested mapping; absent reads as empty.
  ConfigReader Section(const std::string& key) const;
  // A sequence of mappings; absent reads as empty.
  std::vector<ConfigReader> List(const std::string& key) const;

  // Throws ConfigError for the first key in this file that nothing read.
  void CheckAllKeysUsed() const;

  // Throws ConfigError naming this reader's file, `key` and its value.
  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const;

  const std::string& file() const { return file_; }
  // Dotted path of `key` below this reader, e.g. "sim.lidar.num_beams".
  std::string KeyPath(const std::string& key) const;

 private:
  ConfigReader(YAML::Node node, std::string file, std::string path,
               std::shared_ptr<std::set<std::string>> used);
  static ConfigReader FromRoot(YAML::Node root, const std::string& section,
                               const std::string& origin);
  YAML::Node Get(const std::string& key) const;
  std::string ValueText(const std::string& key) const;
  template <typename T>
  void ReadScalar(const std::string& key, T* value, const char* expected) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::shared_ptr<std::set<std::string>> used_paths_;
};

// One `--set KEY=VALUE` override of a config file: a dotted key path and a YAML value.
struct ConfigOverride {
  std::vector<std::string> path;  // "utility.lambda" -> {"utility", "lambda"}
  std::string value;              // YAML text: a scalar ("0.3") or a flow sequence ("[1, 2]")
  std::string Key() const;        // the dotted path again
};

// Parses "a.b.c=VALUE" (split at the first '='). Throws ConfigError naming `argument` for no '=',
// an empty key or key part, an empty value, or a value that is not a YAML scalar or flow
// sequence. Whether the key exists is left to the components' loaders (CheckAllKeysUsed).
ConfigOverride ParseConfigOverride(const std::string& argument);

// The YAML text of `config_file` ("" = the empty defaults) with every override set at its path,
// in order (a later one wins), creating mappings as needed. Comments are not kept. Throws
// ConfigError for an unreadable or malformed file, or a path through a value that is not a
// mapping.
std::string ApplyConfigOverrides(const std::string& config_file,
                                 const std::vector<ConfigOverride>& overrides);

}  // namespace aslam
