#pragma once

// Stuck while exploring (issue 15's definition): the robot stayed within `radius_m` of where it
// was `window_s` earlier, all that time exploring. A livelock (turning in place, a plan flipping
// between two ways) shows as an episode; a pause or a done exploration does not. On value types:
// times are the runner's simulated seconds, positions the true ones.

#include <deque>
#include <optional>
#include <vector>

#include "common/pose2d.h"

namespace aslam {

struct StuckEpisode {
  double start_s = 0.0;         // since when the robot had not left the disk
  double detected_s = 0.0;      // start_s + the window
  std::optional<double> end_s;  // when it left (none: still stuck when the run ended)
  Point2d position_m;           // the disk's centre, "world"
};

struct StuckDetectorOptions {
  double window_s = 120.0;
  double radius_m = 1.0;
  double sample_period_s = 1.0;  // positions kept at most this often
};

class StuckDetector {
 public:
  // Throws std::invalid_argument naming a non-positive option.
  explicit StuckDetector(StuckDetectorOptions options = {});

  // The true position at t_s and whether the exploration is exploring then (EXPLORE_STATUS).
  void OnPosition(double t_s, Point2d position_m, bool exploring);

  const std::vector<StuckEpisode>& episodes() const { return episodes_; }
  // Seconds stuck in all episodes, an open one counted up to `now_s`.
  double StuckSeconds(double now_s) const;

 private:
  struct Sample {
    double t_s;
    Point2d position_m;
  };
  StuckDetectorOptions options_;
  std::deque<Sample> samples_;  // while exploring, the window's and newer
  std::vector<StuckEpisode> episodes_;
};

}  // namespace aslam
