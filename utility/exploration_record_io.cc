#include "utility/exploration_record_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace aslam {

std::string ExplorationRecordToYaml(const ExplorationRecord& record) {
  std::ostringstream out;
  out.precision(17);  // doubles read back exactly
  out << "# aslam-utility state: read back after a restart (--state-file)\n"
      << "decisions: " << record.decisions << "\n"
      << "goals_reached: " << record.goals_reached << "\n"
      << "goals_failed: " << record.goals_failed << "\n"
      << "next_goal_id: " << record.next_goal_id << "\n"
      << "blacklist_m: [";
  for (std::size_t i = 0; i < record.blacklist_m.size(); ++i) {
    out << (i ? ", " : "") << "[" << record.blacklist_m[i].x_m << ", " << record.blacklist_m[i].y_m
        << "]";
  }
  out << "]\n";
  return out.str();
}

ExplorationRecord LoadExplorationRecord(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": cannot read the utility state: " + e.what());
  }
  auto read = [&](const char* key, auto* value) {
    const YAML::Node node = root[key];
    try {
      if (!node) throw std::runtime_error("missing");
      *value = node.as<std::remove_pointer_t<decltype(value)>>();
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ": key " + key + ": " +
                               (node ? "'" + YAML::Dump(node) + "' is not valid" : "missing"));
    }
  };
  ExplorationRecord record;
  read("decisions", &record.decisions);
  read("goals_reached", &record.goals_reached);
  read("goals_failed", &record.goals_failed);
  read("next_goal_id", &record.next_goal_id);
  std::vector<std::vector<double>> points;
  read("blacklist_m", &points);
  for (const std::vector<double>& p : points) {
    if (p.size() != 2 || !std::isfinite(p[0]) || !std::isfinite(p[1])) {
      throw std::runtime_error(path + ": key blacklist_m: every point must be [x, y], finite");
    }
    record.blacklist_m.push_back({p[0], p[1]});
  }
  if (record.decisions < 0 || record.goals_reached < 0 || record.goals_failed < 0 ||
      record.next_goal_id < 0) {
    throw std::runtime_error(path + ": counts and next_goal_id must be >= 0");
  }
  return record;
}

}  // namespace aslam
