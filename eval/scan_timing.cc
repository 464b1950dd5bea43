#include "eval/scan_timing.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "eval/stats.h"

namespace aslam {
namespace {

// Mean capped range residual of `scan` with its stamps moved by `shift_us` (nullopt when
// truth is missing around a beam or no beam could be compared).
std::optional<double> MeanResidual(const LidarScan& scan, const std::vector<TimedPose>& truth,
                                   const SimWorld& world, int64_t shift_us,
                                   const ScanTimingOptions& options) {
  double sum_m = 0.0;
  int beams = 0;
  for (std::size_t i = 0; i < scan.range_m.size(); i += options.beam_stride) {
    if (!scan.IsValidReturn(i)) continue;
    const int64_t beam_utime = scan.utime + std::llround(scan.BeamTimeS(i) * 1e6) + shift_us;
    const auto base = PoseAt(truth, beam_utime, options.max_truth_gap_us);
    if (!base) return std::nullopt;
    const Pose2d sensor = base->Compose(scan.sensor_pose);
    const double expected_m = world.CastRay({sensor.x_m, sensor.y_m},
                                            sensor.yaw_rad + scan.BeamAngle(i), scan.range_max_m);
    if (!std::isfinite(expected_m)) continue;  // nothing there in the truth: not comparable
    sum_m += std::min(std::abs(scan.range_m[i] - expected_m), options.residual_cap_m);
    ++beams;
  }
  if (beams == 0) return std::nullopt;
  return sum_m / beams;
}

// The shift (µs) in [lo, hi] by `step` with the smallest residual; nullopt if none fitted.
std::optional<int64_t> BestShift(const LidarScan& scan, const std::vector<TimedPose>& truth,
                                 const SimWorld& world, int64_t lo_us, int64_t hi_us,
                                 int64_t step_us, const ScanTimingOptions& options) {
  std::optional<int64_t> best;
  double best_residual = 0.0;
  for (int64_t shift = lo_us; shift <= hi_us; shift += step_us) {
    const auto residual = MeanResidual(scan, truth, world, shift, options);
    if (residual && (!best || *residual < best_residual)) {
      best = shift;
      best_residual = *residual;
    }
  }
  return best;
}

}  // namespace

ScanTiming EstimateScanTiming(const std::vector<LidarScan>& scans,
                              const std::vector<TimedPose>& truth, const SimWorld& world,
                              const ScanTimingOptions& options) {
  // Scans taken turning: the yaw rate from truth 50 ms either side of the sweep's middle.
  std::vector<const LidarScan*> turning;
  for (const LidarScan& scan : scans) {
    double sweep_s = 0.0;
    for (const float beam_s : scan.beam_time_s) sweep_s = std::max<double>(sweep_s, beam_s);
    const int64_t middle = scan.utime + std::llround(0.5 * sweep_s * 1e6);
    const auto before = PoseAt(truth, middle - 50000, options.max_truth_gap_us);
    const auto after = PoseAt(truth, middle + 50000, options.max_truth_gap_us);
    if (!before || !after) continue;
    const double rate = std::remainder(after->yaw_rad - before->yaw_rad, 2.0 * M_PI) / 0.1;
    if (std::abs(rate) >= options.min_turn_rate_radps) turning.push_back(&scan);
  }
  if (static_cast<int>(turning.size()) > options.max_scans) {
    std::vector<const LidarScan*> spread;
    for (int k = 0; k < options.max_scans; ++k)
      spread.push_back(turning[k * turning.size() / options.max_scans]);
    turning = std::move(spread);
  }
  const int64_t max_shift_us = std::llround(options.max_shift_ms * 1e3);
  std::vector<double> stamp_late_ms;
  for (const LidarScan* scan : turning) {
    // Coarse (4 ms), then 1 ms around the coarse best.
    const auto coarse = BestShift(*scan, truth, world, -max_shift_us, max_shift_us, 4000, options);
    if (!coarse) continue;
    const auto fine = BestShift(*scan, truth, world, *coarse - 3000, *coarse + 3000, 1000, options);
    if (!fine) continue;
    // Truth at stamp + shift fits: the ranges were measured `shift` after the stamp.
    stamp_late_ms.push_back(-*fine * 1e-3);
  }
  ScanTiming timing;
  timing.scans = static_cast<int>(stamp_late_ms.size());
  timing.median_ms = NearestRankPercentile(stamp_late_ms, 0.5);
  timing.p10_ms = NearestRankPercentile(stamp_late_ms, 0.1);
  timing.p90_ms = NearestRankPercentile(stamp_late_ms, 0.9);
  return timing;
}

}  // namespace aslam
