#include "utility/exploration_record_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace aslam {
namespace {

constexpr std::pair<ControlMode, const char*> kModeNames[] = {
    {ControlMode::kExploring, "exploring"},
    {ControlMode::kPaused, "paused"},
    {ControlMode::kReturning, "returning"},
    {ControlMode::kEnded, "ended"},
};

const char* ModeName(ControlMode mode) {
  for (const auto& [m, name] : kModeNames) {
    if (m == mode) return name;
  }
  return "?";
}

// [[x, y], ...] at the stream's precision.
std::string PointsYaml(const std::vector<Point2d>& points) {
  std::ostringstream out;
  out.precision(17);
  out << "[";
  for (std::size_t i = 0; i < points.size(); ++i) {
    out << (i ? ", " : "") << "[" << points[i].x_m << ", " << points[i].y_m << "]";
  }
  out << "]";
  return out.str();
}

}  // namespace

std::string ExplorationRecordToYaml(const ExplorationRecord& record) {
  std::ostringstream out;
  out.precision(17);  // doubles read back exactly
  out << "# aslam-utility state: read back after a restart (--state-file)\n"
      << "decisions: " << record.decisions << "\n"
      << "goals_reached: " << record.goals_reached << "\n"
      << "goals_failed: " << record.goals_failed << "\n"
      << "next_goal_id: " << record.next_goal_id << "\n"
      << "blacklist_m: " << PointsYaml(record.blacklist_m) << "\n"
      << "retried_m: " << PointsYaml(record.retried_m) << "\n";
  if (record.home_m)
    out << "home_m: [" << record.home_m->x_m << ", " << record.home_m->y_m << "]\n";
  out << "mode: " << ModeName(record.mode) << "\n"
      << "paused_while_returning: " << (record.paused_while_returning ? "true" : "false") << "\n"
      << "ends_done: " << (record.ends_done ? "true" : "false") << "\n"
      << "end_detail: " << YAML::Dump(YAML::Node(record.end_detail)) << "\n";
  return out.str();
}

ExplorationRecord LoadExplorationRecord(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": cannot read the utility state: " + e.what());
  }
  // Keys from before EXPLORE_CONTROL (home_m, mode, ...) are optional: older files still load.
  auto read = [&](const char* key, auto* value, bool optional = false) {
    const YAML::Node node = root[key];
    if (!node && optional) return;
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
  // retried_m came later than blacklist_m: optional, so older files still load.
  for (const auto& [key, points_out, optional] :
       {std::tuple{"blacklist_m", &record.blacklist_m, false},
        std::tuple{"retried_m", &record.retried_m, true}}) {
    std::vector<std::vector<double>> points;
    read(key, &points, optional);
    for (const std::vector<double>& p : points) {
      if (p.size() != 2 || !std::isfinite(p[0]) || !std::isfinite(p[1])) {
        throw std::runtime_error(path + ": key " + key + ": every point must be [x, y], finite");
      }
      points_out->push_back({p[0], p[1]});
    }
  }
  std::vector<double> home;
  read("home_m", &home, /*optional=*/true);
  if (!home.empty()) {
    if (home.size() != 2 || !std::isfinite(home[0]) || !std::isfinite(home[1])) {
      throw std::runtime_error(path + ": key home_m: must be [x, y], finite");
    }
    record.home_m = Point2d{home[0], home[1]};
  }
  std::string mode = ModeName(record.mode);
  read("mode", &mode, /*optional=*/true);
  bool known_mode = false;
  for (const auto& [m, name] : kModeNames) {
    if (mode == name) record.mode = m, known_mode = true;
  }
  if (!known_mode) {
    throw std::runtime_error(path + ": key mode: '" + mode +
                             "': expected exploring, paused, returning or ended");
  }
  read("paused_while_returning", &record.paused_while_returning, /*optional=*/true);
  if ((record.mode == ControlMode::kReturning || record.paused_while_returning) && !record.home_m) {
    throw std::runtime_error(path + ": key home_m: missing, and the way home needs it");
  }
  read("ends_done", &record.ends_done, /*optional=*/true);
  read("end_detail", &record.end_detail, /*optional=*/true);
  if (record.decisions < 0 || record.goals_reached < 0 || record.goals_failed < 0 ||
      record.next_goal_id < 0) {
    throw std::runtime_error(path + ": counts and next_goal_id must be >= 0");
  }
  return record;
}

}  // namespace aslam
