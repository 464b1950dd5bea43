#include "eval/stats.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace aslam {
namespace {

TEST(MeanStdTest, SampleStandardDeviationOverFiniteValues) {
  const MeanStd m = ComputeMeanStd({2.0, 4.0, std::nan(""), 4.0, 4.0, 5.0, 5.0, 7.0, 9.0});
  EXPECT_EQ(m.n, 8);
  EXPECT_DOUBLE_EQ(m.mean, 5.0);
  EXPECT_DOUBLE_EQ(m.std, std::sqrt(32.0 / 7.0));
  EXPECT_EQ(ComputeMeanStd({3.0}).std, 0.0);
  EXPECT_EQ(ComputeMeanStd({}).n, 0);
}

TEST(NearestRankPercentile, IsTheCeilPTimesNthSmallest) {
  const std::vector<double> three = {1.0, 2.0, 3.0};
  EXPECT_EQ(NearestRankPercentile(three, 0.5), 2.0);   // ceil(1.5) = 2nd
  EXPECT_EQ(NearestRankPercentile(three, 0.99), 3.0);  // ceil(2.97) = 3rd
  EXPECT_EQ(NearestRankPercentile(three, 1.0), 3.0);
  EXPECT_EQ(NearestRankPercentile(three, 0.0), 1.0);        // rank 0 clamps to the smallest
  EXPECT_EQ(NearestRankPercentile(three, 1.0 / 3.0), 1.0);  // exactly the 1st, not rounded up
  const std::vector<double> four = {10.0, 20.0, 30.0, 40.0};
  EXPECT_EQ(NearestRankPercentile(four, 0.5),
            20.0);  // ceil(2) = 2nd: the lower middle, never an average
  EXPECT_EQ(NearestRankPercentile({7.0}, 0.99), 7.0);
  EXPECT_EQ(NearestRankPercentile({4.0, 1.0, 3.0, 2.0}, 0.51), 3.0);  // any order
  EXPECT_TRUE(std::isnan(NearestRankPercentile({}, 0.5)));
}

TEST(MedianTest, OddEvenEmptyAndInfinityLast) {
  EXPECT_DOUBLE_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_DOUBLE_EQ(Median({5.0, NAN, 1.0, 3.0}), 3.0);  // NaN dropped
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_TRUE(std::isnan(Median({NAN})));
  EXPECT_DOUBLE_EQ(Median({INFINITY, 3.0, 5.0}), 5.0);  // +inf ranks after every finite value
  EXPECT_EQ(Median({INFINITY, 3.0, INFINITY}), INFINITY);
}

// Reference p-values from scipy.stats.mannwhitneyu(method="asymptotic"), which
// uses the same normal approximation with tie and continuity corrections.
TEST(MannWhitneyTest, MatchesTheNormalApproximation) {
  EXPECT_NEAR(MannWhitneyP({1, 2, 3}, {4, 5, 6}), 0.08085559837005224, 1e-12);
  EXPECT_NEAR(MannWhitneyP({4, 5, 6}, {1, 2, 3}), 0.08085559837005224, 1e-12);  // two-sided
  EXPECT_NEAR(MannWhitneyP({1, 1, 2}, {2, 3, 3}), 0.11014892418594699, 1e-12);  // ties
  EXPECT_NEAR(MannWhitneyP({3, 5, INFINITY}, {4, INFINITY, INFINITY}), 0.6428348264908044, 1e-12);
  std::vector<double> low, high;
  for (int i = 1; i <= 15; ++i) {
    low.push_back(i);
    high.push_back(i + 15);
  }
  EXPECT_NEAR(MannWhitneyP(low, high), 3.3918213908250945e-06, 1e-15);
  EXPECT_DOUBLE_EQ(MannWhitneyP({1, 2, 3}, {1, 2, 3}), 1.0);
  EXPECT_DOUBLE_EQ(MannWhitneyP({2, 2}, {2, 2}), 1.0);
  EXPECT_NEAR(MannWhitneyP({1, NAN, 2, 3}, {4, 5, 6}), 0.08085559837005224, 1e-12);  // NaN dropped
  EXPECT_TRUE(std::isnan(MannWhitneyP({}, {1, 2})));
}

}  // namespace
}  // namespace aslam
