#pragma once

// The utility's state file: the ExplorationRecord as YAML, rewritten atomically whenever it
// changes, so a restarted aslam-utility goes on counting goals and keeps its blacklist.

#include <string>

#include "utility/exploration_manager.h"

namespace aslam {

std::string ExplorationRecordToYaml(const ExplorationRecord& record);
// Throws std::runtime_error naming the file (and the key) when it cannot be read or a value
// is missing or invalid.
ExplorationRecord LoadExplorationRecord(const std::string& path);

}  // namespace aslam
