#include "common/stream_clock.h"

#include <gtest/gtest.h>

namespace aslam {
namespace {

using Verdict = StreamClock::Verdict;
constexpr int64_t kSecond = 1000000;

TEST(StreamClock, OneBadStampIsHeldBackAndTheStreamGoesOn) {
  StreamClock clock(kSecond, 3);
  EXPECT_EQ(clock.Offer(10 * kSecond), Verdict::kInLine);
  EXPECT_EQ(clock.Offer(1000 * kSecond), Verdict::kJump);
  EXPECT_EQ(clock.Offer(10 * kSecond + 100000), Verdict::kInLine);
  EXPECT_EQ(clock.Offer(10 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(10 * kSecond + 100000), Verdict::kBackwards);  // same stamp again
  EXPECT_EQ(clock.Offer(10 * kSecond + 200000), Verdict::kInLine);
  EXPECT_EQ(clock.now_utime(), 10 * kSecond + 200000);
  EXPECT_EQ(clock.resyncs(), 0);
}

TEST(StreamClock, AStepBackIsFollowedAfterResyncMessagesInARow) {
  StreamClock clock(kSecond, 3);
  ASSERT_EQ(clock.Offer(500 * kSecond), Verdict::kInLine);
  EXPECT_EQ(clock.Offer(5 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(5 * kSecond + 100000), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(5 * kSecond + 200000), Verdict::kResynced);
  EXPECT_EQ(clock.now_utime(), 5 * kSecond + 200000);
  EXPECT_EQ(clock.Offer(5 * kSecond + 300000), Verdict::kInLine);
  EXPECT_EQ(clock.resyncs(), 1);
}

TEST(StreamClock, HeldBackStampsMustFollowOneAnother) {
  StreamClock clock(kSecond, 3);
  ASSERT_EQ(clock.Offer(500 * kSecond), Verdict::kInLine);
  // Scattered bad stamps never restart the clock.
  EXPECT_EQ(clock.Offer(5 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(900 * kSecond), Verdict::kJump);
  EXPECT_EQ(clock.Offer(7 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(100 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.resyncs(), 0);
  EXPECT_EQ(clock.now_utime(), 500 * kSecond);
  // A forward step is followed the same way.
  EXPECT_EQ(clock.Offer(2000 * kSecond), Verdict::kJump);
  EXPECT_EQ(clock.Offer(2000 * kSecond + 50000), Verdict::kJump);
  EXPECT_EQ(clock.Offer(2000 * kSecond + 90000), Verdict::kResynced);
}

TEST(StreamClock, MergedStreamsMayRunLateWithoutMovingTheClock) {
  StreamClock clock(kSecond, 3, /*late_tolerance_us=*/kSecond);
  ASSERT_EQ(clock.Offer(10 * kSecond), Verdict::kInLine);
  EXPECT_EQ(clock.Offer(10 * kSecond - 300000), Verdict::kLate);
  EXPECT_EQ(clock.Offer(10 * kSecond), Verdict::kLate);
  EXPECT_EQ(clock.now_utime(), 10 * kSecond);
  EXPECT_EQ(clock.Offer(10 * kSecond + 50000), Verdict::kInLine);
  // Far behind is still a step back, followed after three that agree (in any near order).
  EXPECT_EQ(clock.Offer(2 * kSecond), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(2 * kSecond - 100000), Verdict::kBackwards);
  EXPECT_EQ(clock.Offer(2 * kSecond + 100000), Verdict::kResynced);
  EXPECT_EQ(clock.now_utime(), 2 * kSecond + 100000);
}

}  // namespace
}  // namespace aslam
