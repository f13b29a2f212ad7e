#include "dut_fw/admittance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class AdmittanceTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(AdmittanceTest, Scalars);

template <typename S>
AdmittanceParams<S> Params(S mass_kg, S damping, S stiffness) {
  AdmittanceParams<S> p;
  p.mass_kg = Vec3<S>::Constant(mass_kg);
  p.damping_n_s_per_m = Vec3<S>::Constant(damping);
  p.stiffness_n_per_m = Vec3<S>::Constant(stiffness);
  return p;
}

template <typename S>
Reference<S> SomeReference() {
  Reference<S> r;
  r.position_m = Vec3<S>(S(1), S(2), S(3));
  r.velocity_m_s = Vec3<S>(S(0.5), S(0), S(-0.1));
  r.acceleration_m_s2 = Vec3<S>(S(0), S(0.2), S(0));
  r.yaw_rad = S(0.3);
  return r;
}

TYPED_TEST(AdmittanceTest, ZeroForceKeepsDesiredOnReference) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));
  AdmittanceState<S> state;
  const Reference<S> reference = SomeReference<S>();

  Reference<S> desired;
  for (int i = 0; i < 1000; ++i) {
    desired = StepAdmittance<S>(params, state, reference, Vec3<S>::Zero(), S(1e-3));
  }

  EXPECT_EQ(desired.position_m, reference.position_m);
  EXPECT_EQ(desired.velocity_m_s, reference.velocity_m_s);
  EXPECT_EQ(desired.acceleration_m_s2, reference.acceleration_m_s2);
  EXPECT_EQ(desired.yaw_rad, reference.yaw_rad);
}

TYPED_TEST(AdmittanceTest, ConstantForceSettlesAtForceOverStiffness) {
  using S = TypeParam;
  AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));
  params.stiffness_n_per_m.x() = S(50);
  AdmittanceState<S> state;
  const Reference<S> reference = SomeReference<S>();
  const Vec3<S> force_n(S(1.0), S(-2.0), S(0.5));

  Reference<S> desired;
  for (int i = 0; i < 10000; ++i) {
    desired = StepAdmittance<S>(params, state, reference, force_n, S(1e-3));
  }

  EXPECT_NEAR(state.offset_m.x(), 1.0 / 50.0, 1e-5);
  EXPECT_NEAR(state.offset_m.y(), -2.0 / 36.0, 1e-5);
  EXPECT_NEAR(state.offset_m.z(), 0.5 / 36.0, 1e-5);
  EXPECT_NEAR(state.offset_rate_m_s.norm(), 0.0, 1e-5);
  EXPECT_NEAR(desired.position_m.y(), 2.0 - 2.0 / 36.0, 1e-5);
}

TYPED_TEST(AdmittanceTest, DefaultsStabilityBoundIsAsDocumented) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));

  const S bound_s = MaxStableAdmittanceDt(params);

  // (sqrt(c^2 + 4k) - c) / k with c = 12, k = 36.
  EXPECT_NEAR(bound_s, (std::sqrt(288.0) - 12.0) / 36.0, 1e-6);
  EXPECT_NEAR(bound_s, 0.138, 1e-3);
}

// A stiff, light setting whose bound (34.8 ms) is close to realistic control periods.
TYPED_TEST(AdmittanceTest, StableJustBelowTheDtBound) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(0.1), S(4), S(100));
  const S dt_s = S(0.95) * MaxStableAdmittanceDt(params);
  AdmittanceState<S> state;
  const Vec3<S> force_n(S(1), S(0), S(0));

  for (int i = 0; i < 2000; ++i) {
    StepAdmittance<S>(params, state, SomeReference<S>(), force_n, dt_s);
  }

  EXPECT_NEAR(MaxStableAdmittanceDt(params), (std::sqrt(1600.0 + 4000.0) - 40.0) / 1000.0, 1e-6);
  EXPECT_NEAR(state.offset_m.x(), 0.01, 1e-5);
}

TYPED_TEST(AdmittanceTest, DivergesJustAboveTheDtBound) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(0.1), S(4), S(100));
  const S dt_s = S(1.05) * MaxStableAdmittanceDt(params);
  AdmittanceState<S> state;
  const Vec3<S> force_n(S(1), S(0), S(0));

  for (int i = 0; i < 200; ++i) {
    StepAdmittance<S>(params, state, SomeReference<S>(), force_n, dt_s);
  }

  // The oscillating mode grows by ~1.19 per step: 100x the static answer well within 200 steps.
  EXPECT_TRUE(std::isfinite(state.offset_m.x()));
  EXPECT_GT(std::abs(state.offset_m.x()), 1.0);
}

TYPED_TEST(AdmittanceTest, NonFiniteForceIsIgnoredAndCounted) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));
  AdmittanceState<S> state;
  const Vec3<S> bad(std::numeric_limits<S>::quiet_NaN(), S(0), S(0));

  const Reference<S> desired = StepAdmittance<S>(params, state, SomeReference<S>(), bad, S(1e-3));

  EXPECT_EQ(state.rejected_inputs, 1u);
  EXPECT_EQ(state.offset_m, Vec3<S>::Zero());
  EXPECT_EQ(desired.position_m, SomeReference<S>().position_m);
}

TYPED_TEST(AdmittanceTest, InPlaceStepReportsWhetherTheForceWasFinite) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));
  AdmittanceState<S> state;
  Reference<S> desired;

  const bool nan_used = StepAdmittanceInto<S>(
      params, state, SomeReference<S>(), Vec3<S>(S(1), std::numeric_limits<S>::quiet_NaN(), S(0)),
      S(1e-3), desired);
  const bool finite_used = StepAdmittanceInto<S>(params, state, SomeReference<S>(),
                                                 Vec3<S>(S(2), S(0), S(0)), S(1e-3), desired);

  EXPECT_FALSE(nan_used);
  EXPECT_TRUE(finite_used);
  // The one finite step: rate 2 N / 1 kg * 1 ms = 2 mm/s, offset 2 mm/s * 1 ms = 2 µm.
  EXPECT_NEAR(desired.position_m.x(), 1.000002, 1e-6);
  EXPECT_EQ(desired.yaw_rad, S(0.3));
}

TYPED_TEST(AdmittanceTest, NonPositiveDtHoldsTheOffset) {
  using S = TypeParam;
  const AdmittanceParams<S> params = Params<S>(S(1), S(12), S(36));
  AdmittanceState<S> state;
  state.offset_m = Vec3<S>(S(0.1), S(0), S(0));

  StepAdmittance<S>(params, state, SomeReference<S>(), Vec3<S>(S(5), S(0), S(0)), S(0));

  EXPECT_EQ(state.offset_m.x(), S(0.1));
  EXPECT_EQ(state.offset_rate_m_s.x(), S(0));
  EXPECT_EQ(state.rejected_inputs, 1u);
}

}  // namespace
}  // namespace hilrig::dut_fw
