// The base's safety layer: command timeout, hazards, limits, acceleration.

#include "drivers/kobuki/base_safety.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace aslam {
namespace {

constexpr int64_t kMs = 1000;

VelocityCommand Command(double linear, double angular) {
  VelocityCommand c;
  c.linear_mps = linear;
  c.angular_radps = angular;
  return c;
}

// Steps at the base's 20 ms from `from_ms` to `to_ms`; returns the last output.
Twist Drive(BaseSafety* safety, int from_ms, int to_ms) {
  Twist out;
  for (int t = from_ms; t <= to_ms; t += 20) out = safety->Next(t * kMs);
  return out;
}

TEST(BaseSafety, NothingIsDrivenWithoutACommand) {
  BaseSafety safety(BaseSafetyOptions{});
  const Twist out = Drive(&safety, 0, 1000);
  EXPECT_EQ(out.linear_mps, 0.0);
  EXPECT_TRUE(safety.command_timed_out());
}

TEST(BaseSafety, AccelerationIsLimitedAndSpeedsClamped) {
  BaseSafetyOptions options;  // 0.5 m/s, 1.8 rad/s; 1 m/s², 3 rad/s²
  BaseSafety safety(options);
  safety.Next(0);
  safety.OnCommand(Command(2.0, -5.0), 0);
  Twist out = Drive(&safety, 20, 100);  // 0.1 s of ramp
  EXPECT_NEAR(out.linear_mps, 0.1, 1e-9);
  EXPECT_NEAR(out.angular_radps, -0.3, 1e-9);
  for (int t = 120; t <= 400; t += 100) {
    safety.OnCommand(Command(2.0, -5.0), t * kMs);
    out = Drive(&safety, t, t + 80);
  }
  safety.OnCommand(Command(2.0, -5.0), 500 * kMs);
  out = Drive(&safety, 500, 980);
  EXPECT_NEAR(out.linear_mps, 0.5, 1e-9);
  EXPECT_NEAR(out.angular_radps, -1.8, 1e-9);
}

TEST(BaseSafety, AStaleCommandStopsTheBase) {
  BaseSafety safety(BaseSafetyOptions{});
  safety.Next(0);
  safety.OnCommand(Command(0.3, 0.0), 0);
  EXPECT_NEAR(Drive(&safety, 20, 480).linear_mps, 0.3, 1e-9);
  EXPECT_FALSE(safety.command_timed_out());
  // Past 0.5 s without a newer command: the target is zero, reached at the deceleration limit.
  Twist out = safety.Next(520 * kMs);
  EXPECT_TRUE(safety.command_timed_out());
  EXPECT_LT(out.linear_mps, 0.3);
  out = Drive(&safety, 540, 900);
  EXPECT_EQ(out.linear_mps, 0.0);
}

TEST(BaseSafety, AHazardStopsAtOnceUntilClearedAndCommandedAgain) {
  BaseSafety safety(BaseSafetyOptions{});
  safety.Next(0);
  for (int t = 0; t <= 600; t += 100) {
    safety.OnCommand(Command(0.4, 0.2), t * kMs);
    Drive(&safety, t, t + 80);
  }
  ASSERT_NEAR(safety.last_output().linear_mps, 0.4, 1e-9);
  safety.OnHazards(/*bumper=*/0x02, 0, 0, 700 * kMs);
  EXPECT_EQ(safety.Next(700 * kMs).linear_mps, 0.0);  // no deceleration ramp
  EXPECT_TRUE(safety.hazard_stop());
  // Commands while the bumper is pressed are not obeyed.
  safety.OnCommand(Command(0.4, 0.2), 720 * kMs);
  EXPECT_EQ(Drive(&safety, 720, 800).linear_mps, 0.0);
  // Released: the command from before the release is not obeyed either.
  safety.OnHazards(0, 0, 0, 810 * kMs);
  EXPECT_TRUE(safety.hazard_stop());
  EXPECT_EQ(Drive(&safety, 820, 900).linear_mps, 0.0);
  // A command sent after the release is.
  safety.OnCommand(Command(0.4, 0.2), 910 * kMs);
  EXPECT_FALSE(safety.hazard_stop());
  EXPECT_GT(Drive(&safety, 920, 1000).linear_mps, 0.0);
  // Cliff and wheel drop stop it too.
  safety.OnHazards(0, 0x04, 0, 1010 * kMs);
  EXPECT_EQ(safety.Next(1020 * kMs).linear_mps, 0.0);
  safety.OnHazards(0, 0, 0x01, 1030 * kMs);
  safety.OnCommand(Command(0.4, 0.2), 1040 * kMs);
  EXPECT_EQ(safety.Next(1040 * kMs).linear_mps, 0.0);
}

TEST(BaseSafety, NonFiniteCommandsAreRefused) {
  BaseSafety safety(BaseSafetyOptions{});
  EXPECT_FALSE(safety.OnCommand(Command(std::nan(""), 0.0), 0));
  EXPECT_FALSE(safety.OnCommand(Command(0.1, std::numeric_limits<double>::infinity()), 0));
  EXPECT_EQ(Drive(&safety, 0, 200).linear_mps, 0.0);
}

}  // namespace
}  // namespace aslam
