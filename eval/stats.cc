#include "eval/stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace aslam {

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd out;
  double sum = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    sum += v;
    ++out.n;
  }
  if (out.n == 0) return {std::nan(""), std::nan(""), 0};
  out.mean = sum / out.n;
  double squares = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) squares += (v - out.mean) * (v - out.mean);
  }
  out.std = out.n > 1 ? std::sqrt(squares / (out.n - 1)) : 0.0;
  return out;
}

double Median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }),
               values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2.0;
}

double NearestRankPercentile(std::vector<double> values, double fraction) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  // The epsilon keeps fraction·n that should be an integer (0.99·100) from rounding up past it.
  const double rank = std::ceil(fraction * n - 1e-9);
  return values[static_cast<std::size_t>(std::clamp(rank, 1.0, n)) - 1];
}

double MannWhitneyP(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<std::pair<double, bool>> pooled;  // (value, from a)
  for (const double v : a) {
    if (!std::isnan(v)) pooled.push_back({v, true});
  }
  for (const double v : b) {
    if (!std::isnan(v)) pooled.push_back({v, false});
  }
  std::sort(pooled.begin(), pooled.end());
  double n1 = 0.0, rank_sum_a = 0.0, tie_term = 0.0;
  for (std::size_t i = 0; i < pooled.size();) {
    std::size_t j = i;
    while (j + 1 < pooled.size() && pooled[j + 1].first == pooled[i].first) ++j;
    const double rank = (i + j) / 2.0 + 1.0;  // mid-rank of the tie group
    for (std::size_t k = i; k <= j; ++k) {
      if (pooled[k].second) {
        rank_sum_a += rank;
        n1 += 1.0;
      }
    }
    const double t = static_cast<double>(j - i + 1);
    tie_term += t * t * t - t;
    i = j + 1;
  }
  const double n = static_cast<double>(pooled.size());
  const double n2 = n - n1;
  if (n1 == 0.0 || n2 == 0.0) return std::nan("");
  const double u = rank_sum_a - n1 * (n1 + 1.0) / 2.0;
  const double variance = n1 * n2 / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)));
  if (variance <= 0.0) return 1.0;  // every value tied
  const double z = std::max(0.0, std::abs(u - n1 * n2 / 2.0) - 0.5) / std::sqrt(variance);
  return std::min(1.0, std::erfc(z / std::sqrt(2.0)));
}

}  // namespace aslam
