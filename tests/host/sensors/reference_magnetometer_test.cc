#include "host/sensors/reference_magnetometer.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hilrig::host {
namespace {

MagnetometerParams NoiseFree() {
  MagnetometerParams params;
  params.noise_enabled = false;
  return params;
}

MagnetometerReading SampleOnce(const MagnetometerParams& params, const EarthField& earth,
                               const Eigen::Quaterniond& attitude) {
  MagnetometerState state;
  const auto reading = SampleReferenceMagnetometer(params, earth, state, attitude, 0);
  EXPECT_TRUE(reading.has_value());
  return *reading;
}

TEST(ReferenceMagnetometerTest, LevelAttitudeReadsTheWorldField) {
  const EarthField earth;
  const MagnetometerReading r = SampleOnce(NoiseFree(), earth, Eigen::Quaterniond::Identity());
  EXPECT_LT((r.field_sensor_t - earth.field_world_t).norm(), 1e-20);
  EXPECT_EQ(r.node_id, 7);
  EXPECT_FALSE(r.saturated);
}

TEST(ReferenceMagnetometerTest, NinetyDegreeYawRotatesTheField) {
  // Nose pointing north (body x = world y): the 24 µT north component appears on body x.
  const Eigen::Quaterniond yaw_north(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const MagnetometerReading r = SampleOnce(NoiseFree(), EarthField{}, yaw_north);
  EXPECT_LT((r.field_sensor_t - Eigen::Vector3d(2.4e-5, 0.0, -4.16e-5)).norm(), 1e-18);
}

TEST(ReferenceMagnetometerTest, MountingRotatesIntoTheSensorFrame) {
  // Sensor upside down on the body (180° about body x): y and z flip.
  MagnetometerParams params = NoiseFree();
  params.mounting = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX());
  const MagnetometerReading r = SampleOnce(params, EarthField{}, Eigen::Quaterniond::Identity());
  EXPECT_LT((r.field_sensor_t - Eigen::Vector3d(0.0, -2.4e-5, 4.16e-5)).norm(), 1e-18);
}

TEST(ReferenceMagnetometerTest, CodesAreFieldRoundedToLsb) {
  const MagnetometerReading r =
      SampleOnce(NoiseFree(), EarthField{}, Eigen::Quaterniond::Identity());
  // 0 / 0.150 µT = 0; 24 / 0.150 = 160; -41.6 / 0.242 = -171.9 -> -172.
  EXPECT_EQ(r.code, (std::array<std::int16_t, 3>{0, 160, -172}));
}

TEST(ReferenceMagnetometerTest, QuantizationRoundsHalfAwayFromZero) {
  const Mlx90393Codes codes =
      QuantizeMlx90393(Eigen::Vector3d(1.5e-6, -2.5e-6, 0.4e-6), 1e-6, 1e-6);
  EXPECT_EQ(codes.code, (std::array<std::int16_t, 3>{2, -3, 0}));
  EXPECT_FALSE(codes.saturated);
}

TEST(ReferenceMagnetometerTest, HugeFieldSaturatesAndIsFlagged) {
  EarthField magnet_nearby;
  magnet_nearby.field_world_t = {0.1, -0.1, 1e-6};  // 100 mT: far beyond 32767 LSB
  const MagnetometerReading r =
      SampleOnce(NoiseFree(), magnet_nearby, Eigen::Quaterniond::Identity());
  EXPECT_TRUE(r.saturated);
  EXPECT_EQ(r.code, (std::array<std::int16_t, 3>{32767, -32768, 4}));
}

TEST(ReferenceMagnetometerTest, SamplesAtFiftyHertz) {
  const MagnetometerParams params = NoiseFree();
  MagnetometerState state;
  int count = 0;
  for (std::int64_t now = 0; now < 1'000'000'000; now += 1'000'000) {
    const auto r = SampleReferenceMagnetometer(params, EarthField{}, state,
                                               Eigen::Quaterniond::Identity(), now);
    if (!r) continue;
    EXPECT_EQ(r->time_ns, count * 20'000'000LL);
    EXPECT_EQ(r->sequence, count);
    ++count;
  }
  EXPECT_EQ(count, 50);
}

TEST(ReferenceMagnetometerTest, NoiseMatchesSigma) {
  const MagnetometerParams params;
  MagnetometerState state;
  state.rng = RandomStream::FromSeed(9, StreamId::kReferenceMagnetometer);
  const EarthField earth;
  double sum_sq = 0.0;
  constexpr int kSamples = 20000;
  for (int i = 0; i < kSamples; ++i) {
    const auto r = SampleReferenceMagnetometer(params, earth, state, Eigen::Quaterniond::Identity(),
                                               state.next_sample_ns);
    ASSERT_TRUE(r.has_value());
    sum_sq += (r->field_sensor_t - earth.field_world_t).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum_sq / (3 * kSamples)) / 0.3e-6, 1.0, 0.05);
}

}  // namespace
}  // namespace hilrig::host
