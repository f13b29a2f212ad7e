// ValueCounts: nearest-rank percentiles, exact, against a sorted copy of the samples.
#include "rig/value_counts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace hilrig::rig {
namespace {

TEST(ValueCountsTest, EmptyReadsZero) {
  const ValueCounts counts;
  EXPECT_EQ(counts.count(), 0u);
  EXPECT_EQ(counts.Quantile(0.5), 0u);
  EXPECT_EQ(counts.max(), 0u);
}

TEST(ValueCountsTest, NearestRankOnASmallSet) {
  ValueCounts counts;
  for (std::uint32_t value : {40u, 10u, 30u, 20u}) counts.Add(value);
  EXPECT_EQ(counts.Quantile(0.0), 10u);
  EXPECT_EQ(counts.Quantile(0.25), 10u);  // rank 1
  EXPECT_EQ(counts.Quantile(0.26), 20u);  // rank 2
  EXPECT_EQ(counts.Quantile(0.5), 20u);
  EXPECT_EQ(counts.Quantile(0.99), 40u);
  EXPECT_EQ(counts.Quantile(1.0), 40u);
  EXPECT_EQ(counts.Quantile(7.0), 40u);  // clamped
  EXPECT_EQ(counts.Quantile(-1.0), 10u);
  EXPECT_EQ(counts.Quantile(std::nan("")), 10u);
  EXPECT_EQ(counts.max(), 40u);
  EXPECT_EQ(counts.count(), 4u);
}

TEST(ValueCountsTest, MatchesASortedCopyOfManyRepeatedSamples) {
  std::mt19937 random(7);
  std::uniform_int_distribution<std::uint32_t> work(500, 4000);
  ValueCounts counts;
  std::vector<std::uint32_t> samples;
  for (int i = 0; i < 100'000; ++i) {
    samples.push_back(work(random));
    counts.Add(samples.back());
  }
  std::sort(samples.begin(), samples.end());
  for (double q : {0.01, 0.5, 0.9, 0.99, 0.999}) {
    const auto rank = static_cast<std::size_t>(std::ceil(q * double(samples.size())));
    EXPECT_EQ(counts.Quantile(q), samples[rank - 1]) << q;
  }
  EXPECT_EQ(counts.max(), samples.back());
  EXPECT_EQ(counts.count(), samples.size());
}

TEST(ValueCountsTest, AQuantileThatLandsOnARankIsThatRankNotTheNext) {
  ValueCounts counts;
  for (std::uint32_t value = 1; value <= 25; ++value) counts.Add(value);
  EXPECT_EQ(counts.Quantile(0.28), 7u);  // 0.28 · 25 is 7.000000000000001 in doubles
}

}  // namespace
}  // namespace hilrig::rig
