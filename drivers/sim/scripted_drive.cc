#include "drivers/sim/scripted_drive.h"

#include <algorithm>
#include <cmath>

#include "common/config.h"

namespace aslam {

ScriptedDrive::ScriptedDrive(std::vector<DriveSegment> segments, bool repeat)
    : segments_(std::move(segments)), repeat_(repeat) {
  for (const DriveSegment& segment : segments_) {
    total_us_ += static_cast<int64_t>(std::llround(segment.duration_s * 1e6));
    segment_end_us_.push_back(total_us_);
  }
}

std::optional<VelocityCommand> ScriptedDrive::CommandAt(int64_t utime) const {
  if (total_us_ <= 0 || utime < 0) return std::nullopt;
  int64_t t = utime;
  if (t >= total_us_) {
    if (!repeat_) return std::nullopt;
    t %= total_us_;
  }
  const auto it = std::upper_bound(segment_end_us_.begin(), segment_end_us_.end(), t);
  const DriveSegment& segment = segments_[it - segment_end_us_.begin()];
  return VelocityCommand{utime, segment.linear_mps, segment.angular_radps};
}

ScriptedDrive LoadScriptedDrive(const std::string& file) {
  const ConfigReader reader = ConfigReader::WholeFile(file);
  bool repeat = false;
  reader.Read("repeat", &repeat);
  if (!reader.Has("segments")) reader.Fail("segments", "a drive needs a list of segments");
  std::vector<DriveSegment> segments;
  for (const ConfigReader& item : reader.List("segments")) {
    DriveSegment segment;
    if (!item.Has("duration_s")) item.Fail("duration_s", "every segment needs a duration");
    item.ReadInRange("duration_s", &segment.duration_s, 1e-3, 1e6);
    item.ReadInRange("linear_mps", &segment.linear_mps, -10.0, 10.0);
    item.ReadInRange("angular_radps", &segment.angular_radps, -20.0, 20.0);
    segments.push_back(segment);
  }
  if (segments.empty()) reader.Fail("segments", "a drive needs at least one segment");
  reader.CheckAllKeysUsed();
  return ScriptedDrive(std::move(segments), repeat);
}

}  // namespace aslam
