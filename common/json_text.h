#pragma once

// Writing JSON by hand for the run folder's small files (metrics.json,
// process_stats.json): one escaped string, one number, one flat object.

#include <string>
#include <utility>
#include <vector>

namespace aslam {

// "text" with quotes, backslashes and control characters escaped.
std::string JsonString(const std::string& text);
// %.10g; JSON has no NaN or infinity: those become null.
std::string JsonNumber(double value);
// {"a": 1, "b": 2} on one line, keys in the given order; values are JSON text already.
std::string JsonObject(const std::vector<std::pair<std::string, std::string>>& fields);

}  // namespace aslam
