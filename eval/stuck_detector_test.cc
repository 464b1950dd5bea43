#include "eval/stuck_detector.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace aslam {
namespace {

TEST(StuckDetector, TurningInPlaceForTheWindowIsAnEpisodeUntilTheRobotLeaves) {
  StuckDetector detector;
  // Drives 0.5 m/s for 60 s, then wobbles within 0.3 m for 200 s, then drives off.
  for (int t = 0; t <= 60; ++t) detector.OnPosition(t, {0.5 * t, 0.0}, true);
  for (int t = 61; t <= 260; ++t) detector.OnPosition(t, {30.0 + 0.3 * std::sin(t), 0.0}, true);
  EXPECT_EQ(detector.episodes().size(), 1u);
  EXPECT_FALSE(detector.episodes()[0].end_s.has_value());
  for (int t = 261; t <= 300; ++t) detector.OnPosition(t, {30.0 + 0.5 * (t - 260), 0.0}, true);

  ASSERT_EQ(detector.episodes().size(), 1u);
  const StuckEpisode& e = detector.episodes()[0];
  // At 59 s the robot was at 29.5 m, within 1 m of all the wobble (29.7 to 30.3 m).
  EXPECT_EQ(e.start_s, 59.0);
  EXPECT_EQ(e.detected_s, 179.0);
  ASSERT_TRUE(e.end_s.has_value());
  EXPECT_GE(*e.end_s, 261.0);
  EXPECT_LE(*e.end_s, 264.0);
  EXPECT_NEAR(e.position_m.x_m, 29.5, 1e-9);
  EXPECT_NEAR(detector.StuckSeconds(300.0), *e.end_s - 59.0, 1e-9);
}

TEST(StuckDetector, SlowButSteadyProgressAndPausesAreNotStuck) {
  StuckDetector detector;
  // 1.2 m in every 120 s: slow, but out of any 1 m disk.
  for (int t = 0; t <= 600; ++t) detector.OnPosition(t, {0.01 * t, 0.0}, true);
  EXPECT_TRUE(detector.episodes().empty());
  // Standing still for 300 s while paused or done.
  for (int t = 601; t <= 900; ++t) detector.OnPosition(t, {6.0, 0.0}, false);
  EXPECT_TRUE(detector.episodes().empty());
  // Exploring again: the window starts anew, so 100 s more is not yet stuck.
  for (int t = 901; t <= 1000; ++t) detector.OnPosition(t, {6.0, 0.0}, true);
  EXPECT_TRUE(detector.episodes().empty());
  for (int t = 1001; t <= 1030; ++t) detector.OnPosition(t, {6.0, 0.0}, true);
  ASSERT_EQ(detector.episodes().size(), 1u);
  EXPECT_EQ(detector.episodes()[0].start_s, 901.0);
  EXPECT_EQ(detector.episodes()[0].detected_s, 1021.0);
}

TEST(StuckDetector, BackAndForthWiderThanTheDiskIsNotStuck) {
  StuckDetector detector;
  for (int t = 0; t <= 600; ++t) detector.OnPosition(t, {(t / 10) % 2 == 0 ? 0.0 : 1.5, 0.0}, true);
  EXPECT_TRUE(detector.episodes().empty());
}

TEST(StuckDetector, RejectsNonPositiveOptions) {
  StuckDetectorOptions options;
  options.radius_m = 0.0;
  EXPECT_THROW(StuckDetector{options}, std::invalid_argument);
  options = {};
  options.window_s = std::nan("");
  EXPECT_THROW(StuckDetector{options}, std::invalid_argument);
}

}  // namespace
}  // namespace aslam
