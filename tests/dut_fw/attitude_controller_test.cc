#include "dut_fw/attitude_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hilrig::dut_fw {
namespace {

template <typename S>
class AttitudeControllerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(AttitudeControllerTest, Scalars);

// The gains of DefaultFlightControllerParams, restated so this test depends on the loop alone.
template <typename S>
AttitudeGains<S> Gains() {
  const Vec3<S> inertia(S(3e-3), S(3e-3), S(5e-3));
  AttitudeGains<S> g;
  g.k_r_per_s = Vec3<S>(S(7), S(7), S(4));
  g.k_p_nm_s = S(20) * inertia;
  g.k_i_nm = S(2.5) * g.k_p_nm_s;
  g.k_d_nm_s2 = S(0.03) * g.k_p_nm_s;
  g.max_rate_rad_s = Vec3<S>(S(5), S(5), S(2));
  g.integral_limit_rad = Vec3<S>(S(0.5), S(0.5), S(0.3));
  g.derivative_cutoff_hz = S(30);
  return g;
}

template <typename S>
Quat<S> AboutX(double angle_rad) {
  return Quat<S>(Eigen::AngleAxis<S>(S(angle_rad), Vec3<S>::UnitX()));
}

TYPED_TEST(AttitudeControllerTest, ZeroErrorGivesZeroTorque) {
  using S = TypeParam;
  const Quat<S> q = QuatExp<S>(Vec3<S>(S(0.3), S(-0.2), S(1.0)));
  AttitudeState<S> state;

  Vec3<S> torque;
  for (int i = 0; i < 100; ++i) {
    torque = StepAttitude<S>(Gains<S>(), state, q, q, Vec3<S>::Zero(), S(1e-3));
  }

  EXPECT_NEAR(torque.norm(), 0.0, 1e-9);
}

TYPED_TEST(AttitudeControllerTest, TorqueTurnsTowardTheDesiredAttitude) {
  using S = TypeParam;
  AttitudeState<S> state;

  const Vec3<S> torque = StepAttitude<S>(Gains<S>(), state, AboutX<S>(0.1), Quat<S>::Identity(),
                                         Vec3<S>::Zero(), S(1e-3));

  // First step: no derivative yet; rate demand 7 * 2 sin(0.05) rad/s.
  const double rate_demand = 7.0 * 2.0 * std::sin(0.05);
  EXPECT_NEAR(torque.x(), 0.06 * rate_demand + 0.15 * rate_demand * 1e-3, 1e-6);
  EXPECT_NEAR(torque.y(), 0.0, 1e-9);
  EXPECT_NEAR(torque.z(), 0.0, 1e-9);
}

TYPED_TEST(AttitudeControllerTest, ErrorIsInBodyAxes) {
  using S = TypeParam;
  // Yawed by 90 degrees, body x points along world y: a desired tilt about world y is a rotation
  // about body x, so only the body-x torque may respond.
  const Quat<S> yawed(Eigen::AngleAxis<S>(S(M_PI / 2), Vec3<S>::UnitZ()));
  const Quat<S> desired = Quat<S>(Eigen::AngleAxis<S>(S(0.1), Vec3<S>::UnitY())) * yawed;
  AttitudeState<S> state;

  const Vec3<S> torque =
      StepAttitude<S>(Gains<S>(), state, desired, yawed, Vec3<S>::Zero(), S(1e-3));

  EXPECT_NEAR(torque.x(), 0.06 * 7.0 * 2.0 * std::sin(0.05) * (1.0 + 2.5e-3), 1e-6);
  EXPECT_NEAR(torque.y(), 0.0, 1e-7);
  EXPECT_NEAR(torque.z(), 0.0, 1e-7);
}

// Single-axis rigid body J = 3e-3 kg m², starting 0.5 rad off, 1 kHz, 2 s.
TYPED_TEST(AttitudeControllerTest, SingleAxisRigidBodyConverges) {
  using S = TypeParam;
  const double inertia = 3e-3;
  const double dt = 1e-3;
  double angle = 0.5;
  double rate = 0.0;
  AttitudeState<S> state;
  double max_abs_angle_late = 0.0;

  for (int i = 0; i < 2000; ++i) {
    const Vec3<S> torque = StepAttitude<S>(Gains<S>(), state, Quat<S>::Identity(), AboutX<S>(angle),
                                           Vec3<S>(S(rate), S(0), S(0)), S(dt));
    rate += torque.x() / inertia * dt;
    angle += rate * dt;
    if (i >= 1000) max_abs_angle_late = std::max(max_abs_angle_late, std::abs(angle));
  }

  EXPECT_LT(std::abs(angle), 1e-3);
  EXPECT_LT(std::abs(rate), 1e-2);
  EXPECT_LT(max_abs_angle_late, 5e-3);
}

TYPED_TEST(AttitudeControllerTest, RateDemandIsClamped) {
  using S = TypeParam;
  AttitudeGains<S> gains = Gains<S>();
  gains.k_i_nm.setZero();
  AttitudeState<S> state;

  const Vec3<S> torque =
      StepAttitude<S>(gains, state, AboutX<S>(2.0), Quat<S>::Identity(), Vec3<S>::Zero(), S(1e-3));

  EXPECT_NEAR(torque.x(), 0.06 * 5.0, 1e-6);
}

TYPED_TEST(AttitudeControllerTest, IntegratorIsClamped) {
  using S = TypeParam;
  AttitudeState<S> state;
  const Vec3<S> spinning(S(-1), S(2), S(-3));  // constant rate error, opposite sign

  Vec3<S> torque;
  for (int i = 0; i < 10000; ++i) {
    torque = StepAttitude<S>(Gains<S>(), state, Quat<S>::Identity(), Quat<S>::Identity(), spinning,
                             S(1e-3));
  }

  EXPECT_EQ(state.rate_error_integral.x(), S(0.5));
  EXPECT_EQ(state.rate_error_integral.y(), S(-0.5));
  EXPECT_EQ(state.rate_error_integral.z(), S(0.3));
  EXPECT_NEAR(torque.x(), 0.06 * 1.0 + 0.15 * 0.5, 1e-5);
}

TYPED_TEST(AttitudeControllerTest, DerivativeFollowsARampThroughTheFilter) {
  using S = TypeParam;
  AttitudeState<S> state;
  const double slope = 2.0;  // rad/s² of rate error

  for (int i = 0; i < 200; ++i) {
    const Vec3<S> rate(S(-slope * i * 1e-3), S(0), S(0));
    StepAttitude<S>(Gains<S>(), state, Quat<S>::Identity(), Quat<S>::Identity(), rate, S(1e-3));
  }

  // 200 ms is ~38 filter time constants at 30 Hz.
  EXPECT_NEAR(state.filtered_rate_error_derivative.x(), slope, 1e-3);
}

TYPED_TEST(AttitudeControllerTest, NonPositiveDtFreezesIntegratorAndFilter) {
  using S = TypeParam;
  AttitudeState<S> state;

  StepAttitude<S>(Gains<S>(), state, AboutX<S>(0.1), Quat<S>::Identity(), Vec3<S>::Zero(), S(0));

  EXPECT_EQ(state.rate_error_integral, Vec3<S>::Zero());
  EXPECT_FALSE(state.has_previous);
}

TYPED_TEST(AttitudeControllerTest, GyroscopicFeedForwardIsOmegaCrossJOmega) {
  using S = TypeParam;
  AttitudeGains<S> gains = Gains<S>();
  gains.k_p_nm_s.setZero();
  gains.k_i_nm.setZero();
  gains.k_d_nm_s2.setZero();
  gains.inertia_kg_m2 = Vec3<S>(S(3e-3), S(3e-3), S(5e-3));
  AttitudeState<S> state;
  const Vec3<S> w(S(1), S(2), S(0.5));

  const Vec3<S> torque =
      StepAttitude<S>(gains, state, Quat<S>::Identity(), Quat<S>::Identity(), w, S(1e-3));

  const Vec3<S> expected = w.cross(gains.inertia_kg_m2.cwiseProduct(w));
  EXPECT_NEAR(torque.x(), expected.x(), 1e-9);
  EXPECT_NEAR(torque.y(), expected.y(), 1e-9);
  EXPECT_NEAR(torque.z(), expected.z(), 1e-9);
}

}  // namespace
}  // namespace hilrig::dut_fw
