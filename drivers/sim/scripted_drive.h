#pragma once

// A scripted drive: a list of constant-velocity segments the simulator
// follows in place of a navigator, for demos and recorded fixtures.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/sensor_types.h"

namespace aslam {

struct DriveSegment {
  double duration_s = 0.0;
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

class ScriptedDrive {
 public:
  // `repeat`: start over after the last segment instead of ending.
  explicit ScriptedDrive(std::vector<DriveSegment> segments, bool repeat = false);

  // The command at simulated time `utime` (the drive starts at 0), stamped
  // with that time; nullopt once a non-repeating drive has ended.
  std::optional<VelocityCommand> CommandAt(int64_t utime) const;

  double duration_s() const { return static_cast<double>(total_us_) * 1e-6; }
  const std::vector<DriveSegment>& segments() const { return segments_; }
  bool repeat() const { return repeat_; }

 private:
  std::vector<DriveSegment> segments_;
  std::vector<int64_t> segment_end_us_;  // cumulative end time of each segment
  int64_t total_us_ = 0;
  bool repeat_ = false;
};

// Loads a drive file:
//   repeat: false            # optional
//   segments:
//     - {duration_s: 4.0, linear_mps: 0.4, angular_radps: 0.0}
// Throws ConfigError naming the file, key and value for bad input.
ScriptedDrive LoadScriptedDrive(const std::string& file);

}  // namespace aslam
