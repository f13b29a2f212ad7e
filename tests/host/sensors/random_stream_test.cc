#include "host/sensors/random_stream.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hilrig::host {
namespace {

std::vector<std::uint64_t> Draw(RandomStream rng, int count) {
  std::vector<std::uint64_t> out;
  for (int i = 0; i < count; ++i) out.push_back(rng.NextU64());
  return out;
}

TEST(RandomStreamTest, SameSeedAndStreamGiveSameSequence) {
  EXPECT_EQ(Draw(RandomStream::FromSeed(42, StreamId::kImu), 1000),
            Draw(RandomStream::FromSeed(42, StreamId::kImu), 1000));
}

TEST(RandomStreamTest, DifferentStreamsOrSeedsDiffer) {
  const auto base = Draw(RandomStream::FromSeed(42, StreamId::kImu), 16);
  EXPECT_NE(base, Draw(RandomStream::FromSeed(42, StreamId::kVio), 16));
  EXPECT_NE(base, Draw(RandomStream::FromSeed(43, StreamId::kImu), 16));
  // Seed and stream are not interchangeable.
  EXPECT_NE(Draw(RandomStream::FromSeed(1, 2), 16), Draw(RandomStream::FromSeed(2, 1), 16));
}

TEST(RandomStreamTest, SequenceIsPinnedAcrossPlatforms) {
  // Golden values: a change here breaks the reproducibility of every recorded run.
  RandomStream rng = RandomStream::FromSeed(42, StreamId::kImu);
  EXPECT_EQ(rng.NextU64(), 2140290047560772068ull);
  EXPECT_EQ(rng.NextU64(), 10861404789363124192ull);
  EXPECT_EQ(rng.Gaussian(), 0x1.92e8aad1ff8cdp-1);
}

TEST(RandomStreamTest, CopiesContinueIdentically) {
  RandomStream original = RandomStream::FromSeed(7, StreamId::kReferenceMagnetometer);
  original.Gaussian();
  RandomStream copy = original;
  for (int i = 0; i < 100; ++i) EXPECT_EQ(original.Gaussian(), copy.Gaussian());
  EXPECT_EQ(original, copy);
}

TEST(RandomStreamTest, Uniform01StaysInUnitIntervalWithMeanOneHalf) {
  RandomStream rng = RandomStream::FromSeed(3, StreamId::kVio);
  constexpr int kSamples = 100000;
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double u = rng.Uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  // sigma of the mean = sqrt(1/12 / n) ~ 9e-4.
  EXPECT_NEAR(sum / kSamples, 0.5, 5e-3);
}

TEST(RandomStreamTest, GaussianHasZeroMeanAndUnitVariance) {
  RandomStream rng = RandomStream::FromSeed(11, TactileStreamId(3));
  constexpr int kSamples = 100000;
  double sum = 0.0, sum_sq = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = rng.Gaussian();
    sum += x;
    sum_sq += x * x;
  }
  const double mean = sum / kSamples;
  const double variance = sum_sq / kSamples - mean * mean;
  // 5 sigma: mean sigma = 1/sqrt(n) ~ 3.2e-3, variance sigma = sqrt(2/n) ~ 4.5e-3.
  EXPECT_NEAR(mean, 0.0, 0.016);
  EXPECT_NEAR(variance, 1.0, 0.023);
}

TEST(RandomStreamTest, GaussianTailProbabilitiesMatchTheNormal) {
  // Exercises the ziggurat's wedge and tail paths, which mean and variance barely see.
  RandomStream rng = RandomStream::FromSeed(12, StreamId::kImu);
  constexpr int kSamples = 1'000'000;
  const double thresholds[] = {0.5, 1.0, 2.0, 3.0, 3.6541528853610088, 4.0};
  int beyond[6] = {};
  for (int i = 0; i < kSamples; ++i) {
    const double x = std::abs(rng.Gaussian());
    for (int k = 0; k < 6; ++k) beyond[k] += x > thresholds[k] ? 1 : 0;
  }
  for (int k = 0; k < 6; ++k) {
    const double p = std::erfc(thresholds[k] / std::sqrt(2.0));
    const double sigma = std::sqrt(p * (1.0 - p) / kSamples);
    EXPECT_NEAR(static_cast<double>(beyond[k]) / kSamples, p, 5.0 * sigma)
        << "P(|x| > " << thresholds[k] << ")";
  }
}

TEST(RandomStreamTest, GaussianVectorIsThreeGaussiansInOrderThroughWedgeAndTail) {
  // 300 000 vectors: some 13 000 draws take the wedge and tail paths.
  RandomStream vectors = RandomStream::FromSeed(21, StreamId::kImu);
  RandomStream singles = vectors;
  for (int i = 0; i < 300'000; ++i) {
    const Eigen::Vector3d v = StandardGaussianVector(vectors);
    const double x = singles.Gaussian();
    const double y = singles.Gaussian();
    const double z = singles.Gaussian();
    ASSERT_EQ(v, Eigen::Vector3d(x, y, z)) << i;
  }
  EXPECT_EQ(vectors, singles);
}

TEST(RandomStreamTest, FilledGaussiansAreSinglesInOrderThroughWedgeAndTail) {
  // 25 000 batches of twelve (the IMU's batch): some 4 500 draws take the wedge and tail paths.
  RandomStream batches = RandomStream::FromSeed(22, StreamId::kImu);
  RandomStream singles = batches;
  for (int i = 0; i < 25'000; ++i) {
    std::array<double, 12> batch;
    FillStandardGaussians(batches, batch);
    for (int k = 0; k < 12; ++k) ASSERT_EQ(batch[k], singles.Gaussian()) << i << " " << k;
  }
  EXPECT_EQ(batches, singles);
}

TEST(RandomStreamTest, FillingNoGaussiansDrawsNothing) {
  RandomStream rng = RandomStream::FromSeed(23, StreamId::kImu);
  const RandomStream before = rng;
  std::array<double, 1> untouched = {7.0};
  FillStandardGaussians(rng, std::span<double>(untouched).first(0));
  EXPECT_EQ(rng, before);
  EXPECT_EQ(untouched[0], 7.0);
}

TEST(RandomStreamTest, GaussianSequenceIsPinnedPastTheSlowPaths) {
  // Golden, recorded with the float-compare ziggurat of 5e31f0d: the 10 000th draw of this stream
  // and the sum of all 10 000 (about 150 of them wedge or tail draws) pin every accept/reject
  // decision, not just the first draw.
  RandomStream rng = RandomStream::FromSeed(42, StreamId::kImu);
  double sum = 0.0;
  double last = 0.0;
  for (int i = 0; i < 10'000; ++i) sum += (last = rng.Gaussian());
  EXPECT_EQ(last, 0x1.ff85a741e75ep-1);
  EXPECT_EQ(sum, -0x1.4beb0d4135106p+6);
}

TEST(RandomStreamTest, TactileStreamIdsCoverTheReservedRange) {
  EXPECT_EQ(TactileStreamId(0), StreamId::kTactileFirst);
  EXPECT_EQ(TactileStreamId(6), StreamId::kTactileLast);
}

}  // namespace
}  // namespace hilrig::host
