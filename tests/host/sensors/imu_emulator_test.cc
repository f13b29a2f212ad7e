#include "host/sensors/imu_emulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hilrig::host {
namespace {

const Eigen::Vector3d kRate(0.1, -0.2, 0.3);
const Eigen::Vector3d kSpecificForce(0.5, -0.4, 9.81);

struct Stats {
  Eigen::Vector3d mean;
  Eigen::Vector3d stddev;
};

// Statistics of the reading errors (gyro when use_gyro, else accel) over n samples.
Stats ErrorStats(const ImuParams& params, ImuState& state, int n, bool use_gyro) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const ImuReading r = SampleImu(params, state, kRate, kSpecificForce, i * 1'000'000LL);
    const Eigen::Vector3d e = use_gyro ? Eigen::Vector3d(r.gyro_rad_s - kRate)
                                       : Eigen::Vector3d(r.accel_m_s2 - kSpecificForce);
    sum += e;
    sum_sq += e.cwiseProduct(e);
  }
  const Eigen::Vector3d mean = sum / n;
  return {mean, (sum_sq / n - mean.cwiseProduct(mean)).cwiseSqrt()};
}

ImuParams WhiteNoiseOnly() {
  ImuParams params;
  params.gyro_bias_sigma_rad_s = 0.0;
  params.gyro_bias_random_walk_rad_s2_sqrt_hz = 0.0;
  params.accel_bias_sigma_m_s2 = 0.0;
  params.accel_bias_random_walk_m_s3_sqrt_hz = 0.0;
  return params;
}

TEST(ImuEmulatorTest, NoiseFreeReadingEqualsTruth) {
  ImuParams params;
  params.noise_enabled = false;
  ImuState state = MakeImuState(params, RandomStream::FromSeed(1, StreamId::kImu));
  const ImuReading reading = SampleImu(params, state, kRate, kSpecificForce, 123'456'789);
  EXPECT_EQ(reading.time_ns, 123'456'789);
  EXPECT_EQ(reading.gyro_rad_s, kRate);
  EXPECT_EQ(reading.accel_m_s2, kSpecificForce);
}

TEST(ImuEmulatorTest, GyroWhiteNoiseStdIsDensityTimesSqrtRate) {
  const ImuParams params = WhiteNoiseOnly();
  ImuState state = MakeImuState(params, RandomStream::FromSeed(2, StreamId::kImu));
  const Stats stats = ErrorStats(params, state, 100000, /*use_gyro=*/true);
  const double expected = 1.7e-4 * std::sqrt(1000.0);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(stats.stddev(axis) / expected, 1.0, 0.05);
}

TEST(ImuEmulatorTest, AccelWhiteNoiseStdIsDensityTimesSqrtRate) {
  const ImuParams params = WhiteNoiseOnly();
  ImuState state = MakeImuState(params, RandomStream::FromSeed(3, StreamId::kImu));
  const Stats stats = ErrorStats(params, state, 100000, /*use_gyro=*/false);
  const double expected = 2e-3 * std::sqrt(1000.0);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(stats.stddev(axis) / expected, 1.0, 0.05);
}

TEST(ImuEmulatorTest, ReadingsAreDeterministicPerSeed) {
  const ImuParams params;
  ImuState a = MakeImuState(params, RandomStream::FromSeed(5, StreamId::kImu));
  ImuState b = MakeImuState(params, RandomStream::FromSeed(5, StreamId::kImu));
  ImuState other = MakeImuState(params, RandomStream::FromSeed(6, StreamId::kImu));
  bool any_different = false;
  for (int i = 0; i < 100; ++i) {
    const ImuReading ra = SampleImu(params, a, kRate, kSpecificForce, i);
    const ImuReading rb = SampleImu(params, b, kRate, kSpecificForce, i);
    const ImuReading ro = SampleImu(params, other, kRate, kSpecificForce, i);
    ASSERT_EQ(ra.gyro_rad_s, rb.gyro_rad_s);
    ASSERT_EQ(ra.accel_m_s2, rb.accel_m_s2);
    any_different |= ra.gyro_rad_s != ro.gyro_rad_s;
  }
  EXPECT_TRUE(any_different);
}

// A device makes the noise scales once; its readings are the per-sample computation's, bit for
// bit, and draw the stream alike.
TEST(ImuEmulatorTest, ScalesMadeOnceGiveTheSameReadings) {
  ImuParams params;
  params.rate_hz = 400;
  const ImuNoiseScales scales = MakeImuNoiseScales(params);
  EXPECT_EQ(scales.gyro_noise_rad_s, params.gyro_noise_density_rad_s_sqrt_hz * std::sqrt(400.0));
  EXPECT_EQ(scales.accel_walk_m_s2, params.accel_bias_random_walk_m_s3_sqrt_hz / std::sqrt(400.0));
  ImuState per_sample = MakeImuState(params, RandomStream::FromSeed(5, StreamId::kImu));
  ImuState once = per_sample;
  for (int i = 0; i < 100; ++i) {
    const ImuReading a = SampleImu(params, per_sample, kRate, kSpecificForce, i);
    const ImuReading b = SampleImu(params, scales, once, kRate, kSpecificForce, i);
    ASSERT_EQ(a.gyro_rad_s, b.gyro_rad_s);
    ASSERT_EQ(a.accel_m_s2, b.accel_m_s2);
    ASSERT_EQ(per_sample.gyro_bias_rad_s, once.gyro_bias_rad_s);
    ASSERT_EQ(per_sample.accel_bias_m_s2, once.accel_bias_m_s2);
  }
}

TEST(ImuEmulatorTest, TurnOnBiasSpreadMatchesSigma) {
  const ImuParams params;
  double sum_sq = 0.0;
  constexpr int kSeeds = 4000;
  for (int seed = 0; seed < kSeeds; ++seed) {
    const ImuState state = MakeImuState(params, RandomStream::FromSeed(seed, StreamId::kImu));
    sum_sq += state.gyro_bias_rad_s.squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum_sq / (3 * kSeeds)) / 0.005, 1.0, 0.05);
}

TEST(ImuEmulatorTest, BiasRandomWalkStepMatchesDensityOverSqrtRate) {
  ImuParams params = WhiteNoiseOnly();
  params.gyro_noise_density_rad_s_sqrt_hz = 0.0;  // reading differences are then bias steps
  params.gyro_bias_random_walk_rad_s2_sqrt_hz = 1e-3;
  ImuState state = MakeImuState(params, RandomStream::FromSeed(8, StreamId::kImu));
  Eigen::Vector3d previous = SampleImu(params, state, kRate, kSpecificForce, 0).gyro_rad_s;
  double sum_sq = 0.0;
  constexpr int kSamples = 50000;
  for (int i = 1; i <= kSamples; ++i) {
    const Eigen::Vector3d gyro = SampleImu(params, state, kRate, kSpecificForce, i).gyro_rad_s;
    sum_sq += (gyro - previous).squaredNorm();
    previous = gyro;
  }
  const double expected = 1e-3 / std::sqrt(1000.0);
  EXPECT_NEAR(std::sqrt(sum_sq / (3 * kSamples)) / expected, 1.0, 0.05);
}

// A touchdown's spike (about 13 000 m/s² at a hard landing) and a spin past the gyro's range read
// as a real MEMS IMU reads them: each axis at its full scale, ±16 g and ±2000 °/s, and flagged.
TEST(ImuEmulatorTest, AReadingPastFullScaleSaturatesAndIsFlagged) {
  for (const bool noise : {false, true}) {
    ImuParams params;
    params.noise_enabled = noise;
    ImuState state = MakeImuState(params, RandomStream::FromSeed(3, StreamId::kImu));
    const ImuReading spike = SampleImu(params, state, Eigen::Vector3d(0, -60.0, 1.0),
                                       Eigen::Vector3d(0.5, 0, -13000.0), 0);
    EXPECT_EQ(spike.accel_m_s2.z(), -16 * 9.80665) << noise;
    EXPECT_NEAR(spike.accel_m_s2.x(), 0.5, 0.5) << "an axis within range is untouched";
    EXPECT_NEAR(spike.gyro_rad_s.y(), -2000 * std::numbers::pi / 180, 1e-12) << noise;
    EXPECT_TRUE(spike.accel_clipped);
    EXPECT_TRUE(spike.gyro_clipped);
    const ImuReading calm = SampleImu(params, state, kRate, kSpecificForce, 1);
    EXPECT_FALSE(calm.accel_clipped);
    EXPECT_FALSE(calm.gyro_clipped);
  }
  ImuParams narrow;
  narrow.noise_enabled = false;
  narrow.accel_range_m_s2 = 2 * 9.80665;  // a ±2 g part
  ImuState state = MakeImuState(narrow, RandomStream::FromSeed(3, StreamId::kImu));
  EXPECT_EQ(SampleImu(narrow, state, kRate, Eigen::Vector3d(0, 0, 30), 0).accel_m_s2.z(),
            2 * 9.80665);
}

}  // namespace
}  // namespace hilrig::host
