// The plotted series' decimation: exact while short, bounded however long, and never losing an
// extreme or a gap.
#include "host/trace/decimated_series.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hilrig::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kMax = DecimatedSeries::kMaxBuckets;

double Wave(std::uint64_t i) { return std::sin(static_cast<double>(i) * 0.001); }

std::size_t CountNaN(const std::vector<double>& values) {
  return static_cast<std::size_t>(
      std::count_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }));
}

TEST(DecimatedSeriesTest, AShortSeriesComesBackExactly) {
  DecimatedSeries series;
  std::vector<double> time_s, value;
  for (std::size_t i = 0; i < 2 * kMax; ++i) {  // up to two samples per bucket: all kept
    time_s.push_back(0.01 * static_cast<double>(i));
    value.push_back(Wave(i * 37));
    series.Add(time_s.back(), value.back());
  }

  const DecimatedSeries::Points points = series.ToPoints();

  EXPECT_EQ(points.time_s, time_s);
  EXPECT_EQ(points.value, value);
}

TEST(DecimatedSeriesTest, StaysBoundedHoweverLong) {
  DecimatedSeries series;
  const std::uint64_t n = 3'000'001;
  for (std::uint64_t i = 0; i < n; ++i) series.Add(0.01 * static_cast<double>(i), Wave(i));

  EXPECT_EQ(series.samples_added(), n);
  EXPECT_LE(series.bucket_count(), kMax);
  EXPECT_GE(series.bucket_count(), kMax / 2);
  EXPECT_GE(series.bucket_width_n(), n / kMax);
  const DecimatedSeries::Points points = series.ToPoints();
  EXPECT_LE(points.time_s.size(), 6 * kMax);
  EXPECT_EQ(points.time_s.size(), points.value.size());
  EXPECT_TRUE(std::is_sorted(points.time_s.begin(), points.time_s.end()));
  // The line still spans the whole run.
  EXPECT_EQ(points.time_s.front(), 0.0);
  EXPECT_EQ(points.time_s.back(), 0.01 * static_cast<double>(n - 1));
}

// A one-sample spike up or down, anywhere in a long run, is still in the plot.
TEST(DecimatedSeriesTest, KeepsEveryOneSampleSpike) {
  DecimatedSeries series;
  const std::uint64_t n = 1'000'000, spacing = 9'973;
  std::vector<double> spikes;
  for (std::uint64_t i = 0; i < n; ++i) {
    double value = 0.001 * Wave(i);
    if (i % spacing == 17) {
      value = (i / spacing % 2 == 0 ? 1.0 : -1.0) * (2.0 + static_cast<double>(i) * 1e-6);
      spikes.push_back(value);
    }
    series.Add(static_cast<double>(i), value);
  }

  const DecimatedSeries::Points points = series.ToPoints();

  for (double spike : spikes) {
    EXPECT_NE(std::find(points.value.begin(), points.value.end(), spike), points.value.end())
        << spike;
  }
  EXPECT_LT(points.value.size(), n / 100);
}

TEST(DecimatedSeriesTest, KeepsTheExtremesOfTheWholeSeries) {
  DecimatedSeries series;
  double lowest = 1e9, highest = -1e9;
  for (std::uint64_t i = 0; i < 500'000; ++i) {
    const double value = Wave(i * 7) + 1e-7 * static_cast<double>(i % 1013);
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
    series.Add(static_cast<double>(i), value);
  }

  const DecimatedSeries::Points points = series.ToPoints();

  EXPECT_EQ(*std::min_element(points.value.begin(), points.value.end()), lowest);
  EXPECT_EQ(*std::max_element(points.value.begin(), points.value.end()), highest);
}

// A gap stays a gap (a NaN value) after decimation, and a non-finite sample is never an extreme.
TEST(DecimatedSeriesTest, KeepsAGapAndNeverPlotsANonFiniteValue) {
  DecimatedSeries series;
  const std::uint64_t n = 400'000;
  for (std::uint64_t i = 0; i < n; ++i) {
    double value = Wave(i);
    if (i == 123'457) value = kNaN;
    if (i == 234'567) value = std::numeric_limits<double>::infinity();
    if (i == 345'678) value = -std::numeric_limits<double>::infinity();
    series.Add(static_cast<double>(i), value);
  }
  series.Add(kNaN, 0.5);  // a sample without a time is a gap too

  const DecimatedSeries::Points points = series.ToPoints();

  EXPECT_GE(CountNaN(points.value), 4u);
  for (std::size_t i = 0; i < points.value.size(); ++i) {
    EXPECT_FALSE(std::isinf(points.value[i])) << i;
  }
  EXPECT_TRUE(std::isnan(points.value.back()));
  EXPECT_TRUE(std::isnan(points.time_s.back()));
  EXPECT_NE(std::find(points.time_s.begin(), points.time_s.end(), 123'457.0), points.time_s.end());
}

TEST(DecimatedSeriesTest, AllGapsGiveNoFiniteValue) {
  DecimatedSeries series;
  for (std::uint64_t i = 0; i < 100'000; ++i) series.Add(static_cast<double>(i), kNaN);

  const DecimatedSeries::Points points = series.ToPoints();

  ASSERT_FALSE(points.value.empty());
  EXPECT_EQ(CountNaN(points.value), points.value.size());
  EXPECT_LE(points.value.size(), 2 * kMax);
}

TEST(DecimatedSeriesTest, AnEmptySeriesHasNoPoints) {
  const DecimatedSeries series;
  EXPECT_TRUE(series.ToPoints().time_s.empty());
  EXPECT_EQ(series.bucket_count(), 0u);
}

}  // namespace
}  // namespace hilrig::host
