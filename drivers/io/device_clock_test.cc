// DeviceClock: a device's clock on the host's, from arrival times alone.

#include "drivers/io/device_clock.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace aslam {
namespace {

TEST(DeviceClock, TheOffsetIsTheQuickestTransferAndJitterTheSpread) {
  DeviceClock clock;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> latency_ms(1.0, 5.0);  // USB: 1-5 ms after stamping
  const int64_t boot_utime = 123456789;  // the host time of the device's time 0
  int64_t last_mapped = 0;
  double sum = 0, sum_sq = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const int64_t device_us = i * 20000;
    const double latency = latency_ms(rng);
    sum += latency;
    sum_sq += latency * latency;
    const int64_t arrival = boot_utime + device_us + std::llround(latency * 1000);
    const int64_t mapped = clock.Map(device_us, arrival);
    EXPECT_LE(mapped, arrival);
    EXPECT_GT(mapped, last_mapped);
    last_mapped = mapped;
    if (i > 200) {
      // The true stamp's host time plus at most the smallest latency seen (about 1 ms).
      EXPECT_GE(mapped, boot_utime + device_us);
      EXPECT_LE(mapped, boot_utime + device_us + 1100);
    }
  }
  EXPECT_NEAR(clock.offset_ms(), boot_utime * 1e-3 + 1.0, 0.1);
  const double mean = sum / n;
  EXPECT_NEAR(clock.jitter_ms(), std::sqrt(sum_sq / n - mean * mean), 0.1);  // ~1.15 ms
  EXPECT_EQ(clock.resets(), 0);
}

TEST(DeviceClock, ADeviceResetStartsOver) {
  DeviceClock clock;
  for (int i = 0; i < 100; ++i) clock.Map(5000000 + i * 20000, 9000000 + i * 20000 + 2000);
  // The device restarted its clock at 0 while the host ran on.
  const int64_t mapped = clock.Map(0, 11000000 + 3000);
  EXPECT_EQ(clock.resets(), 1);
  EXPECT_EQ(mapped, 11000000 + 3000);  // the only sample: its arrival
  EXPECT_EQ(clock.Map(20000, 11020000 + 2000), 11020000 + 2000);
  EXPECT_EQ(clock.Map(40000, 11040000 + 4000), 11040000 + 2000);  // the quicker one sets it
}

TEST(DeviceClock, DriftIsFollowedWithinTheWindow) {
  DeviceClock clock(/*window_s=*/10.0);
  // The device's crystal runs 200 ppm slow; 5 minutes at 50 Hz, 1 ms latency.
  for (int i = 0; i < 15000; ++i) {
    const int64_t host_true = i * 20000;
    const int64_t device_us = std::llround(host_true * (1.0 - 200e-6));
    const int64_t mapped = clock.Map(device_us, host_true + 1000);
    // An old minimum can be stale by at most the window's drift: 10 s * 200 ppm = 2 ms.
    EXPECT_NEAR(static_cast<double>(mapped - host_true), 1000.0, 2100.0) << i;
  }
}

}  // namespace
}  // namespace aslam
