#include "eval/stuck_detector.h"

#include <cmath>
#include <stdexcept>

#include "common/text_format.h"

namespace aslam {
namespace {

double Distance(Point2d a, Point2d b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

}  // namespace

StuckDetector::StuckDetector(StuckDetectorOptions options) : options_(options) {
  for (const auto& [name, value] : {std::pair<const char*, double>{"window_s", options.window_s},
                                    {"radius_m", options.radius_m},
                                    {"sample_period_s", options.sample_period_s}}) {
    if (!(value > 0) || !std::isfinite(value)) {
      throw std::invalid_argument(Format("stuck detector: %s must be > 0, got %g", name, value));
    }
  }
}

void StuckDetector::OnPosition(double t_s, Point2d position_m, bool exploring) {
  const bool episode_open = !episodes_.empty() && !episodes_.back().end_s;
  if (!exploring) {
    samples_.clear();  // the window starts again when exploring does
    if (episode_open) episodes_.back().end_s = t_s;
    return;
  }
  if (!samples_.empty() && t_s < samples_.back().t_s + options_.sample_period_s) return;
  samples_.push_back({t_s, position_m});
  // The front stays the newest sample at least a window old.
  while (samples_.size() >= 2 && samples_[1].t_s <= t_s - options_.window_s) samples_.pop_front();
  const Sample& front = samples_.front();
  bool stuck = front.t_s <= t_s - options_.window_s;
  for (const Sample& s : samples_) {
    if (!stuck) break;
    stuck = Distance(s.position_m, front.position_m) <= options_.radius_m;
  }
  if (stuck && !episode_open) {
    episodes_.push_back({front.t_s, t_s, std::nullopt, front.position_m});
  } else if (!stuck && episode_open) {
    episodes_.back().end_s = t_s;
  }
}

double StuckDetector::StuckSeconds(double now_s) const {
  double total_s = 0.0;
  for (const StuckEpisode& e : episodes_) total_s += e.end_s.value_or(now_s) - e.start_s;
  return total_s;
}

}  // namespace aslam
