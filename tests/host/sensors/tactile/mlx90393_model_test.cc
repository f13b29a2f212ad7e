#include "host/sensors/tactile/mlx90393_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hilrig::host {
namespace {

Mlx90393Params Ideal() {
  Mlx90393Params params;
  params.noise_enabled = false;
  params.drift_enabled = false;
  return params;
}

Mlx90393Sample SampleOnce(const Mlx90393Params& params, const Eigen::Vector3d& field_t,
                          double temperature_c = 25.0) {
  Mlx90393State state;
  return SampleMlx90393(params, state, field_t, temperature_c);
}

// The test's own reading of a result word back to signed counts (datasheet encoding).
std::int32_t Counts(std::uint16_t code, int res) {
  if (res == 2) return static_cast<std::int32_t>(code) - 0x8000;
  if (res == 3) return static_cast<std::int32_t>(code) - 0x4000;
  return static_cast<std::int16_t>(code);
}

double Lsb(int gain, int res, int axis) {
  const dut_fw::Mlx90393Setting setting{static_cast<std::uint8_t>(gain),
                                        static_cast<std::uint8_t>(res)};
  return dut_fw::LsbTesla<double>(setting)[axis];
}

Mlx90393Params IdealAt(int gain, int res) {
  Mlx90393Params params = Ideal();
  params.setting = {static_cast<std::uint8_t>(gain), static_cast<std::uint8_t>(res)};
  return params;
}

TEST(Mlx90393ModelTest, DefaultsToTheMostSensitiveSetting) {
  const Mlx90393Params params;
  EXPECT_DOUBLE_EQ(Lsb(params.setting.gain_sel, params.setting.resolution, 0), 0.150e-6);
  EXPECT_DOUBLE_EQ(Lsb(params.setting.gain_sel, params.setting.resolution, 2), 0.242e-6);
}

TEST(Mlx90393ModelTest, CodesAreFieldOverLsbForEveryGainAndRes) {
  const Eigen::Vector3d field_t(1.234e-3, -0.567e-3, 2.345e-3);
  for (int gain = 0; gain < 8; ++gain) {
    for (int res = 0; res < 4; ++res) {
      const Mlx90393Sample s = SampleOnce(IdealAt(gain, res), field_t);
      ASSERT_FALSE(s.saturated) << gain << " " << res;
      for (int axis = 0; axis < 3; ++axis) {
        const double expected = std::round(field_t[axis] / Lsb(gain, res, axis));
        EXPECT_EQ(Counts(s.code[axis], res), expected) << gain << " " << res << " " << axis;
      }
    }
  }
}

TEST(Mlx90393ModelTest, EncodingOffsetsDependOnRes) {
  const std::array<std::uint16_t, 4> zero_codes = {0x0000, 0x0000, 0x8000, 0x4000};
  const std::array<std::uint16_t, 4> minus_ten_codes = {0xFFF6, 0xFFF6, 0x7FF6, 0x3FF6};
  for (int res = 0; res < 4; ++res) {
    const Mlx90393Params params = IdealAt(7, res);
    EXPECT_EQ(SampleOnce(params, Eigen::Vector3d::Zero()).code[0], zero_codes[res]) << res;
    const Eigen::Vector3d minus_ten(-10 * Lsb(7, res, 0), 0.0, 0.0);
    EXPECT_EQ(SampleOnce(params, minus_ten).code[0], minus_ten_codes[res]) << res;
  }
}

TEST(Mlx90393ModelTest, EncodingOffMeansTwosComplementForEveryRes) {
  for (int res = 0; res < 4; ++res) {
    Mlx90393Params params = IdealAt(7, res);
    params.encoding_enabled = false;
    const Eigen::Vector3d minus_ten(-10 * Lsb(7, res, 0), 0.0, 0.0);
    EXPECT_EQ(SampleOnce(params, minus_ten).code[0], 0xFFF6) << res;
  }
}

TEST(Mlx90393ModelTest, InsideTheRangeIsNotSaturated) {
  const Mlx90393Sample s = SampleOnce(IdealAt(7, 3), Eigen::Vector3d(10999 * Lsb(7, 3, 0), 0, 0));
  EXPECT_FALSE(s.saturated);
  EXPECT_EQ(Counts(s.code[0], 3), 10999);
}

TEST(Mlx90393ModelTest, BeyondTheRangeClipsToTheRailAndFlags) {
  // Rails: RES 0 int16, RES 2 +-22000 around 0x8000, RES 3 +-11000 around 0x4000.
  const Mlx90393Sample res0 =
      SampleOnce(IdealAt(7, 0), Eigen::Vector3d(40000 * Lsb(7, 0, 0), 0, 0));
  EXPECT_TRUE(res0.saturated);
  EXPECT_EQ(res0.code[0], 0x7FFF);
  const Mlx90393Sample res2 =
      SampleOnce(IdealAt(7, 2), Eigen::Vector3d(0, -30000 * Lsb(7, 2, 1), 0));
  EXPECT_TRUE(res2.saturated);
  EXPECT_EQ(res2.code[1], 0x8000 - 22000);
  const Mlx90393Sample res3 =
      SampleOnce(IdealAt(7, 3), Eigen::Vector3d(0, 0, 20000 * Lsb(7, 3, 2)));
  EXPECT_TRUE(res3.saturated);
  EXPECT_EQ(res3.code[2], 0x4000 + 11000);
}

TEST(Mlx90393ModelTest, ExactlyOnTheRailIsFlaggedBecauseAReaderCannotTellItFromBeyond) {
  const Mlx90393Sample s = SampleOnce(IdealAt(7, 0), Eigen::Vector3d(32767 * Lsb(7, 0, 0), 0, 0));
  EXPECT_TRUE(s.saturated);
  EXPECT_EQ(s.code[0], 0x7FFF);
}

TEST(Mlx90393ModelTest, SaturationOffWrapsButStillFlags) {
  Mlx90393Params params = Ideal();
  params.saturation_enabled = false;
  const Mlx90393Sample s = SampleOnce(params, Eigen::Vector3d(32768 * Lsb(7, 0, 0), 0.0, 0.0));
  EXPECT_TRUE(s.saturated);
  EXPECT_EQ(s.code[0], 0x8000);  // +32768 wraps to -32768
}

TEST(Mlx90393ModelTest, NonFiniteFieldIsFlaggedNotSilent) {
  const Mlx90393Sample s = SampleOnce(Ideal(), Eigen::Vector3d(std::nan(""), 0.0, 0.0));
  EXPECT_TRUE(s.saturated);
}

TEST(Mlx90393ModelTest, NoiseStdMatchesTheSetValue) {
  Mlx90393Params params = Ideal();
  params.noise_enabled = true;
  Mlx90393State state{RandomStream::FromSeed(1234, TactileStreamId(0))};
  const int n = 100000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  const Eigen::Vector3d field_t(20e-6, -30e-6, 40e-6);
  for (int i = 0; i < n; ++i) {
    const Mlx90393Sample s = SampleMlx90393(params, state, field_t, 25.0);
    for (int axis = 0; axis < 3; ++axis) {
      const double b = Counts(s.code[axis], 0) * Lsb(7, 0, axis);
      sum[axis] += b;
      sum_sq[axis] += b * b;
    }
  }
  const Eigen::Vector3d expected(params.noise_xy_t, params.noise_xy_t, params.noise_z_t);
  for (int axis = 0; axis < 3; ++axis) {
    const double mean = sum[axis] / n;
    const double std = std::sqrt(sum_sq[axis] / n - mean * mean);
    EXPECT_NEAR(std, expected[axis], 0.05 * expected[axis]) << axis;
    EXPECT_NEAR(mean, field_t[axis], 0.05 * expected[axis]) << axis;
  }
}

TEST(Mlx90393ModelTest, WarmerChipRaisesTheOffsetInTheDocumentedDirection) {
  Mlx90393Params params = Ideal();
  params.drift_enabled = true;
  const Mlx90393Sample cool = SampleOnce(params, Eigen::Vector3d::Zero(), 25.0);
  const Mlx90393Sample warm = SampleOnce(params, Eigen::Vector3d::Zero(), 65.0);
  // +0.1 uT/K x 40 K = 4 uT = 26.7 LSB on x.
  EXPECT_EQ(Counts(cool.code[0], 0), 0);
  EXPECT_EQ(Counts(warm.code[0], 0), std::lround(4e-6 / 0.150e-6));
  EXPECT_GT(Counts(warm.code[2], 0), 0);
}

TEST(Mlx90393ModelTest, WarmerChipLowersTheSensitivity) {
  Mlx90393Params params = Ideal();
  params.drift_enabled = true;
  params.offset_tempco_t_per_k = Eigen::Vector3d::Zero();
  const Eigen::Vector3d field_t(0.0, 0.0, 3e-3);
  const std::int32_t cool = Counts(SampleOnce(params, field_t, 25.0).code[2], 0);
  const std::int32_t warm = Counts(SampleOnce(params, field_t, 65.0).code[2], 0);
  EXPECT_LT(warm, cool);
  EXPECT_NEAR(static_cast<double>(warm) / cool, 1.0 - 0.0003 * 40, 1e-4);
}

TEST(Mlx90393ModelTest, DriftOffIgnoresTemperature) {
  const Eigen::Vector3d field_t(1e-3, 2e-3, 3e-3);
  EXPECT_EQ(SampleOnce(Ideal(), field_t, -20.0).code, SampleOnce(Ideal(), field_t, 85.0).code);
}

}  // namespace
}  // namespace hilrig::host

namespace hilrig::host {
namespace {

TEST(QuantizeMlx90393AxisTest, RoundsHalfAwayFromZeroAndClips) {
  EXPECT_EQ(QuantizeMlx90393Axis(1.5e-6, 1e-6, -10, 10).counts, 2);
  EXPECT_EQ(QuantizeMlx90393Axis(-2.5e-6, 1e-6, -10, 10).counts, -3);
  EXPECT_FALSE(QuantizeMlx90393Axis(-2.5e-6, 1e-6, -10, 10).clipped);
  EXPECT_EQ(QuantizeMlx90393Axis(1.0, 1e-6, -10, 10).counts, 10);
  EXPECT_TRUE(QuantizeMlx90393Axis(1.0, 1e-6, -10, 10).clipped);
  EXPECT_TRUE(QuantizeMlx90393Axis(std::nan(""), 1e-6, -10, 10).clipped);
}

TEST(QuantizeMlx90393AxisTest, HalvesJustBelowAndLargeOrInfiniteFieldsRoundAsStdRound) {
  // The largest double below 0.5 stays at 0 (adding 0.5 first would round it up to 1).
  EXPECT_EQ(QuantizeMlx90393Axis(0.49999999999999994, 1.0, -10, 10).counts, 0);
  EXPECT_EQ(QuantizeMlx90393Axis(-0.49999999999999994, 1.0, -10, 10).counts, 0);
  EXPECT_EQ(QuantizeMlx90393Axis(7.5, 1.0, -10, 10).counts, 8);
  EXPECT_EQ(QuantizeMlx90393Axis(-7.5, 1.0, -10, 10).counts, -8);
  EXPECT_EQ(QuantizeMlx90393Axis(-7.4999999999999991, 1.0, -10, 10).counts, -7);
  // Beyond 2^52 every double is an integer already; Inf clips to the rail it points at.
  EXPECT_EQ(QuantizeMlx90393Axis(0x1.0p60, 1.0, -10, 10).counts, 10);
  EXPECT_EQ(QuantizeMlx90393Axis(-INFINITY, 1.0, -10, 10).counts, -10);
  EXPECT_TRUE(QuantizeMlx90393Axis(INFINITY, 1.0, -10, 10).clipped);
  EXPECT_EQ(QuantizeMlx90393Axis(INFINITY, 1.0, -10, 10).counts, 10);
}

TEST(Mlx90393ModelTest, ConstantsBuiltOnceGiveTheSameConversionsAsOneOffCalls) {
  Mlx90393Params params;
  params.setting = {3, 2};
  const Mlx90393Constants constants = MakeMlx90393Constants(params);
  EXPECT_DOUBLE_EQ(constants.lsb_t.x(), 0.376e-6 * 4);
  EXPECT_DOUBLE_EQ(constants.lsb_t.z(), 0.605e-6 * 4);
  EXPECT_EQ(constants.range.zero_code, 32768);
  Mlx90393State once{RandomStream::FromSeed(5, TactileStreamId(2))};
  Mlx90393State each = once;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d field_t(1e-5 * i, -3e-5, 4e-5);
    EXPECT_EQ(SampleMlx90393(params, constants, once, field_t, 31.0).code,
              SampleMlx90393(params, each, field_t, 31.0).code)
        << i;
  }
}

}  // namespace
}  // namespace hilrig::host
