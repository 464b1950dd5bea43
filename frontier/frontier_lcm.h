#pragma once

// FRONTIERS translators.

#include <optional>

#include "aslam/frontier_list_t.hpp"
#include "frontier/frontier.h"

namespace aslam {

// Cells are not carried (points_m are); FromLcm leaves `cells` empty.
frontier_list_t ToLcm(const FrontierList& list);
// Rejects counts that disagree with the arrays (size_cells included),
// non-finite coordinates, and negative or repeated ids.
std::optional<FrontierList> FromLcm(const frontier_list_t& msg);

}  // namespace aslam
