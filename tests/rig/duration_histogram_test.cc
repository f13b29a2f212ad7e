#include "rig/duration_histogram.h"

#include <gtest/gtest.h>

#include <limits>

namespace hilrig::rig {
namespace {

TEST(DurationHistogram, EmptyHistogramSummarisesToZeros) {
  const DurationHistogram histogram;
  const DurationSummary summary = histogram.Summary();
  EXPECT_EQ(summary.count, 0u);
  EXPECT_EQ(summary.p99_s, 0.0);
  EXPECT_EQ(summary.max_s, 0.0);
}

TEST(DurationHistogram, PercentilesOfOneToHundredMicroseconds) {
  DurationHistogram histogram;
  // 100 samples of 1..100 µs, in scrambled order: p50 is the 50th smallest, p99 the 99th.
  for (int i = 0; i < 100; ++i) histogram.Add(((i * 37) % 100 + 1) * 1'000);
  const DurationSummary summary = histogram.Summary();
  EXPECT_EQ(summary.count, 100u);
  EXPECT_NEAR(summary.p50_s, 50e-6, 1e-6);
  EXPECT_NEAR(summary.p99_s, 99e-6, 1e-6);
  EXPECT_DOUBLE_EQ(summary.max_s, 100e-6);
  EXPECT_NEAR(summary.mean_s, 50.5e-6, 1e-12);
}

TEST(DurationHistogram, OneLateOutlierShowsInMaxNotInP50) {
  DurationHistogram histogram;
  for (int i = 0; i < 999; ++i) histogram.Add(1'000'000);  // 1 ms periods
  histogram.Add(250'000'000);                              // one 250 ms stall, past the buckets
  const DurationSummary summary = histogram.Summary();
  EXPECT_NEAR(summary.p50_s, 1e-3, 1e-6);
  EXPECT_NEAR(summary.p99_s, 1e-3, 1e-6);
  EXPECT_DOUBLE_EQ(summary.max_s, 0.25);
  EXPECT_DOUBLE_EQ(histogram.QuantileS(1.0), 0.25);
}

TEST(DurationHistogram, NegativeSamplesAreCountedApart) {
  DurationHistogram histogram;
  histogram.Add(-5);
  histogram.Add(2'000);
  const DurationSummary summary = histogram.Summary();
  EXPECT_EQ(summary.count, 1u);
  EXPECT_EQ(summary.rejected, 1u);
  EXPECT_DOUBLE_EQ(summary.max_s, 2e-6);
}

TEST(DurationHistogram, QuantileOfNanIsZeroNotGarbage) {
  DurationHistogram histogram;
  histogram.Add(3'000);
  EXPECT_EQ(histogram.QuantileS(std::numeric_limits<double>::quiet_NaN()), 0.0);
}

}  // namespace
}  // namespace hilrig::rig
