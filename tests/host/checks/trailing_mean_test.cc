// The trailing mean an envelope's mean_over_s reads: what a sum over the window gives, non-finite
// values ruling it only while they are in the window, and a cost per sample that does not grow
// with the window.
#include "host/checks/trailing_mean.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <numeric>

namespace hilrig::host {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Samples one per second; a span of 3.5 s keeps the last four.
TEST(TrailingMeanTest, IsTheMeanOfTheSamplesInTheWindow) {
  TrailingMean mean;
  EXPECT_TRUE(std::isnan(mean.Mean()));
  const double values[] = {1, 2, 3, 4, 5, 6};
  for (int i = 0; i < 6; ++i) mean.Add(i, values[i], 3.5);
  EXPECT_EQ(mean.size(), 4u);
  EXPECT_EQ(mean.Mean(), (3.0 + 4 + 5 + 6) / 4);
}

// A span of 1.5 s keeps the last two samples.
TEST(TrailingMeanTest, ANonFiniteValueRulesTheMeanOnlyWhileInTheWindow) {
  TrailingMean mean;
  mean.Add(0, 1, 1.5);
  mean.Add(1, kNaN, 1.5);
  EXPECT_TRUE(std::isnan(mean.Mean()));
  mean.Add(2, kInf, 1.5);
  EXPECT_TRUE(std::isnan(mean.Mean()));
  mean.Add(3, 2, 1.5);
  EXPECT_EQ(mean.Mean(), kInf);
  mean.Add(4, -kInf, 1.5);
  EXPECT_EQ(mean.Mean(), -kInf);
  mean.Add(5, kInf, 1.5);
  EXPECT_TRUE(std::isnan(mean.Mean()));  // both infinities, as a plain sum gives
  mean.Add(6, 4, 1.5);
  EXPECT_EQ(mean.Mean(), kInf);
  mean.Add(7, 6, 1.5);
  EXPECT_EQ(mean.Mean(), 5.0);
}

// Ones added while values of 1e16 are in the window round away in a running sum; the fresh sums
// leave none of that behind once the large values are gone.
TEST(TrailingMeanTest, RoundingDoesNotOutliveTheValuesThatCausedIt) {
  TrailingMean mean;
  int t = 0;
  for (int i = 0; i < 100; ++i) mean.Add(t++, 1e16 + 2 * i, 99.5);
  for (int i = 0; i < 300; ++i) mean.Add(t++, 1.0, 99.5);
  EXPECT_EQ(mean.size(), 100u);
  EXPECT_EQ(mean.Mean(), 1.0);
}

TEST(TrailingMeanTest, ASpanShorterThanASampleHoldsNone) {
  TrailingMean mean;
  mean.Add(0, 1, 0);
  EXPECT_EQ(mean.size(), 0u);
  EXPECT_TRUE(std::isnan(mean.Mean()));
}

// 200 000 samples through a 10 000-sample window: the mean stays that of a sum over the window
// (both round at about 1e-14 of the 1e9 offset), and the values summed stay about three per
// sample, where summing the window at every sample adds up 1.9e9.
TEST(TrailingMeanTest, CostPerSampleDoesNotGrowWithTheWindow) {
  constexpr int kSamples = 200'000;
  constexpr int kWindow = 10'000;
  TrailingMean mean;
  std::deque<double> window;
  for (int i = 0; i < kSamples; ++i) {
    const double value = 1e9 + std::sin(i * 0.37) * 1e3;
    mean.Add(i, value, kWindow - 0.5);
    window.push_back(value);
    if (window.size() > kWindow) window.pop_front();
    if (i % 9973 == 0) {
      const double direct = std::accumulate(window.begin(), window.end(), 0.0) / window.size();
      EXPECT_NEAR(mean.Mean(), direct, 1e-12 * direct) << "at sample " << i;
    }
  }
  EXPECT_EQ(mean.size(), static_cast<std::size_t>(kWindow));
  EXPECT_LE(mean.values_summed(), 3u * kSamples);
}

}  // namespace
}  // namespace hilrig::host
