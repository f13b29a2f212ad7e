#include "dut_fw/geomagnetic_compensation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class GeomagneticCompensationTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(GeomagneticCompensationTest, Scalars);

template <typename S>
Mat3<S> RotationFromAxisAngle(double angle_rad, const Vec3<double>& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix().cast<S>();
}

TYPED_TEST(GeomagneticCompensationTest, RotatedEarthFieldIsRemoved) {
  using S = TypeParam;
  const Vec3<S> earth_world_t(S(0), S(2.4e-5), S(-4.16e-5));
  const Vec3<S> film_t(S(8e-4), S(-3e-4), S(-4.5e-3));  // film field at sensor i, sensor axes
  const Mat3<S> body_from_sensor = RotationFromAxisAngle<S>(1.2, {0.3, -1.0, 0.2});
  const Mat3<S> body_from_reference = RotationFromAxisAngle<S>(-0.4, {1.0, 0.5, 0.0});
  const Mat3<S> sensor_from_reference = body_from_sensor.transpose() * body_from_reference;
  const S tolerance =
      S(16) * std::numeric_limits<S>::epsilon() * (film_t.norm() + earth_world_t.norm());
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> angle(-3.14, 3.14), component(-1.0, 1.0);

  for (int i = 0; i < 100; ++i) {
    const Mat3<S> world_from_body =
        RotationFromAxisAngle<S>(angle(rng), {component(rng), component(rng), component(rng)});
    const Vec3<S> sensor_t =
        film_t + (world_from_body * body_from_sensor).transpose() * earth_world_t;
    const Vec3<S> reference_t = (world_from_body * body_from_reference).transpose() * earth_world_t;

    const Vec3<S> compensated_t = CompensateField<S>(sensor_from_reference, sensor_t, reference_t);

    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(compensated_t[axis], film_t[axis], tolerance) << i << " " << axis;
    }
  }
}

TYPED_TEST(GeomagneticCompensationTest, CompensatedReadingCarriesEitherReadingsFlags) {
  using S = TypeParam;
  const Mat3<S> identity = Mat3<S>::Identity();
  const FieldReading<S> good{Vec3<S>(S(1e-3), S(0), S(-4e-3)), false, true};
  const FieldReading<S> clipped{Vec3<S>(S(3e-5), S(0), S(0)), true, true};
  const FieldReading<S> invalid{Vec3<S>::Zero(), false, false};

  const FieldReading<S> reference_clipped = CompensateReading<S>(identity, good, clipped);
  const FieldReading<S> sensor_invalid = CompensateReading<S>(identity, invalid, good);
  const FieldReading<S> both_good = CompensateReading<S>(identity, good, good);

  EXPECT_TRUE(reference_clipped.saturated);
  EXPECT_TRUE(reference_clipped.valid);
  EXPECT_FALSE(sensor_invalid.valid);
  EXPECT_FALSE(both_good.saturated);
  EXPECT_TRUE(both_good.valid);
  EXPECT_EQ(both_good.field_t, Vec3<S>::Zero());
}

TYPED_TEST(GeomagneticCompensationTest, OffsetMakesTheMeanNoLoadForceZero) {
  using S = TypeParam;
  const FilmConstants<S> film = FilmConstants<S>::Published();
  const Vec3<S> a(S(1.8), S(-2.2), S(0.9));
  const Vec3<S> no_load_t(S(2e-5), S(-1e-5), S(-4.8e-3));
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise_t(0.0, 0.3e-6);
  std::vector<SVector<S>> samples;
  for (int i = 0; i < 200; ++i) {
    const Vec3<S> field_t = no_load_t + Vec3<S>(S(noise_t(rng)), S(noise_t(rng)), S(noise_t(rng)));
    samples.push_back(ComputeS<S>(film, field_t));
  }
  ZeroOffsetState<S> state;

  for (const SVector<S>& sample : samples) AddNoLoadSample(state, sample);
  const ForceCalibration<S> calibration{a, ZeroOffset(state, a)};

  Vec3<double> mean_force_n = Vec3<double>::Zero();
  for (const SVector<S>& sample : samples) {
    const ForceResult<S> force = ForceFromS<S>(calibration, sample);
    ASSERT_TRUE(force.ok());
    mean_force_n += force.force_n.template cast<double>() / double(samples.size());
  }
  EXPECT_EQ(state.count, 200u);
  EXPECT_LT(mean_force_n.cwiseAbs().maxCoeff(), 1e-5);
}

TYPED_TEST(GeomagneticCompensationTest, FlaggedSamplesAreRejectedAndCounted) {
  using S = TypeParam;
  const SVector<S> good{Vec3<S>(S(0.1), S(-0.2), S(-6.0)), DecodeStatus::kOk};
  const SVector<S> saturated{Vec3<S>::Zero(), DecodeStatus::kSaturated};
  // A flagged sample with garbage in it, as a caller that ignored the contract might build.
  const SVector<S> singular{Vec3<S>::Constant(S(1e6)), DecodeStatus::kBzPrimeSingular};
  ZeroOffsetState<S> state;

  for (int i = 0; i < 10; ++i) {
    AddNoLoadSample(state, good);
    AddNoLoadSample(state, i % 2 == 0 ? saturated : singular);
  }

  EXPECT_EQ(state.count, 10u);
  EXPECT_EQ(state.rejected, 10u);
  const Vec3<S> b = ZeroOffset(state, Vec3<S>::Ones());
  EXPECT_NEAR(b.x(), S(-0.1), S(1e-5));
  EXPECT_NEAR(b.y(), S(0.2), S(1e-5));
  EXPECT_NEAR(b.z(), S(6.0), S(1e-5));
}

TYPED_TEST(GeomagneticCompensationTest, NotReadyUntilEnoughAcceptedSamples) {
  using S = TypeParam;
  const SVector<S> good{Vec3<S>(S(0.1), S(-0.2), S(-6.0)), DecodeStatus::kOk};
  const SVector<S> flagged{Vec3<S>::Zero(), DecodeStatus::kNonFiniteInput};
  ZeroOffsetState<S> state;

  for (int i = 0; i < 49; ++i) AddNoLoadSample(state, good);
  for (int i = 0; i < 10; ++i) AddNoLoadSample(state, flagged);
  const bool ready_at_49 = ZeroOffsetReady(state, 50);
  AddNoLoadSample(state, good);
  const bool ready_at_50 = ZeroOffsetReady(state, 50);

  EXPECT_FALSE(ready_at_49);
  EXPECT_TRUE(ready_at_50);
}

TYPED_TEST(GeomagneticCompensationTest, OffsetBeforeAnySampleIsNanAndRefusedByTheDecoder) {
  using S = TypeParam;
  const ZeroOffsetState<S> empty;
  const SVector<S> s{Vec3<S>(S(0.1), S(-0.2), S(-6.0)), DecodeStatus::kOk};

  const Vec3<S> b = ZeroOffset(empty, Vec3<S>::Ones());
  const ForceResult<S> force = ForceFromS<S>({Vec3<S>::Ones(), b}, s);

  EXPECT_FALSE(ZeroOffsetReady(empty, 0));
  EXPECT_TRUE(std::isnan(b.x()) && std::isnan(b.y()) && std::isnan(b.z()));
  EXPECT_EQ(force.status, DecodeStatus::kNonFiniteInput);
}

}  // namespace
}  // namespace hilrig::dut_fw
