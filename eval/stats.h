#pragma once

// Summary statistics of the benches (docs/architecture.md §6): mean ± std,
// median and the Mann–Whitney U test over per-run values. No I/O.

#include <vector>

namespace aslam {

// Mean and sample standard deviation (n − 1) of the finite values; NaN if none
// (std 0 for one value).
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
  int n = 0;
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

// Median of the non-NaN values; +inf values rank last (a run that never got
// there counts as later than every run that did). NaN if there is no value.
double Median(std::vector<double> values);

// Nearest-rank percentile: the ceil(fraction·n)-th smallest value, fraction in [0, 1] (0 gives
// the smallest), so always a value that occurred, never an average; NaN for no values.
double NearestRankPercentile(std::vector<double> values, double fraction);

// Two-sided Mann–Whitney U test of a against b: the normal approximation with
// tie and continuity corrections. NaN values are dropped and +inf ranks last;
// NaN if either sample is empty.
double MannWhitneyP(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace aslam
