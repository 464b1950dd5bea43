#include "eval/scan_timing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/sim/lidar_models.h"
#include "drivers/sim/sim_test_world.h"
#include "drivers/sim/simulator.h"

namespace aslam {
namespace {

struct Recording {
  std::vector<LidarScan> scans;
  std::vector<TimedPose> truth;
};

// Six seconds of a simulated RPLIDAR A2 (swept, 10 Hz, with range noise) on a robot
// driving a tight circle (1 rad/s): every scan is taken while turning.
Recording RecordCircle() {
  SimulatorOptions options;
  options.lidar = LidarModelOptions("rplidar_a2");
  Simulator simulator(RoomWithPillar(), {3.0, 4.0, 0.0}, options);
  Recording recording;
  while (simulator.utime() < 6000000) {
    simulator.SetCommand({simulator.utime(), 0.2, 1.0});
    const SimStepOutput out = simulator.Step();
    if (out.scan) recording.scans.push_back(*out.scan);
    if (out.truth) recording.truth.push_back({out.truth->utime, out.truth->pose});
  }
  return recording;
}

std::vector<LidarScan> StampedLate(std::vector<LidarScan> scans, int64_t late_us) {
  for (LidarScan& scan : scans) scan.utime += late_us;
  return scans;
}

TEST(ScanTiming, FindsHowLateOrEarlyTheStampsAre) {
  const Recording recording = RecordCircle();
  const SimWorld world(RoomWithPillar());
  const ScanTiming exact = EstimateScanTiming(recording.scans, recording.truth, world);
  // The first second speeds up to 1 rad/s; the rest are turning scans.
  EXPECT_GE(exact.scans, 40);
  EXPECT_NEAR(exact.median_ms, 0.0, 1.5);
  for (const int late_ms : {12, -8, 25}) {
    SCOPED_TRACE(late_ms);
    const ScanTiming timing =
        EstimateScanTiming(StampedLate(recording.scans, late_ms * 1000), recording.truth, world);
    EXPECT_NEAR(timing.scans, exact.scans, 2);  // a scan at the end of speeding up may flip
    EXPECT_NEAR(timing.median_ms, late_ms, 1.5);
    EXPECT_LE(timing.p10_ms, timing.median_ms);
    EXPECT_GE(timing.p90_ms, timing.median_ms);
  }
}

TEST(ScanTiming, NothingToFitWithoutTurnsOrTruth) {
  const Recording recording = RecordCircle();
  const SimWorld world(RoomWithPillar());
  EXPECT_EQ(EstimateScanTiming(recording.scans, {}, world).scans, 0);
  EXPECT_TRUE(std::isnan(EstimateScanTiming(recording.scans, {}, world).median_ms));
  ScanTimingOptions faster_turns_only;
  faster_turns_only.min_turn_rate_radps = 2.0;
  EXPECT_EQ(EstimateScanTiming(recording.scans, recording.truth, world, faster_turns_only).scans,
            0);
}

}  // namespace
}  // namespace aslam
