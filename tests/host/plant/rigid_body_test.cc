#include "host/plant/rigid_body.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/long_run.h"

namespace hilrig::host {
namespace {

constexpr double kG = 9.81;

double FreeFallDropError(Integrator integrator, double dt_s, int steps) {
  RigidBodyParams params;
  RigidBodyState state;
  state.position_m = {0.0, 0.0, 100.0};
  for (int i = 0; i < steps; ++i) state = StepRigidBody(params, state, {}, kG, dt_s, integrator);
  const double t = dt_s * steps;
  const double expected_drop = 0.5 * kG * t * t;
  return (100.0 - state.position_m.z()) - expected_drop;
}

TEST(RigidBodyTest, FreeFallWithRk4MatchesClosedForm) {
  const double t = 2.0;
  const double error = FreeFallDropError(Integrator::kRk4, 1e-3, 2000);
  EXPECT_LT(std::abs(error) / (0.5 * kG * t * t), 1e-9);
}

TEST(RigidBodyTest, FreeFallWithSemiImplicitEulerIsFirstOrderInDt) {
  // Semi-implicit Euler drops by g t^2 / 2 + g t dt / 2: the excess halves with dt.
  const double t = 2.0;
  const double error_coarse = FreeFallDropError(Integrator::kSemiImplicitEuler, 2e-3, 1000);
  const double error_fine = FreeFallDropError(Integrator::kSemiImplicitEuler, 1e-3, 2000);
  EXPECT_NEAR(error_coarse, 0.5 * kG * t * 2e-3, 1e-9);
  EXPECT_NEAR(error_coarse / error_fine, 2.0, 1e-6);
}

TEST(RigidBodyTest, VelocityFollowsAppliedForce) {
  RigidBodyParams params;
  RigidBodyState state;
  Wrench wrench;
  wrench.force_world_n = {params.mass_kg * 1.0, 0.0, params.mass_kg * kG};  // 1 m/s^2 forward
  for (int i = 0; i < 1000; ++i) {
    state = StepRigidBody(params, state, wrench, kG, 1e-3, Integrator::kRk4);
  }
  EXPECT_NEAR(state.velocity_m_s.x(), 1.0, 1e-12);
  EXPECT_NEAR(state.position_m.x(), 0.5, 1e-12);
  EXPECT_NEAR(state.position_m.z(), 0.0, 1e-12);
}

RigidBodyState SpinningState() {
  RigidBodyState state;
  state.angular_velocity_rad_s = {3.0, -1.0, 2.0};
  return state;
}

RigidBodyParams AsymmetricBody() {
  RigidBodyParams params;
  params.inertia_kg_m2 = {2e-3, 3e-3, 5e-3};  // all distinct so the gyroscopic term matters
  return params;
}

TEST(RigidBodyTest, TorqueFreeSpinConservesKineticEnergy) {
  const RigidBodyParams params = AsymmetricBody();
  RigidBodyState state = SpinningState();
  const double energy_before = MechanicalEnergy(params, state, kG);
  for (int i = 0; i < 10000; ++i) {
    state = StepRigidBody(params, state, {}, kG, 1e-3, Integrator::kRk4);
  }
  EXPECT_NEAR(MechanicalEnergy(params, state, kG) / energy_before, 1.0, 1e-8);
  // The gyroscopic term actually moved the rate vector around in the body frame.
  EXPECT_GT((state.angular_velocity_rad_s - SpinningState().angular_velocity_rad_s).norm(), 0.1);
}

TEST(RigidBodyTest, TorqueFreeSpinConservesAngularMomentumInWorld) {
  const RigidBodyParams params = AsymmetricBody();
  RigidBodyState state = SpinningState();
  const Eigen::Vector3d momentum_before = AngularMomentumWorld(params, state);
  for (int i = 0; i < 10000; ++i) {
    state = StepRigidBody(params, state, {}, kG, 1e-3, Integrator::kRk4);
  }
  const Eigen::Vector3d momentum_after = AngularMomentumWorld(params, state);
  EXPECT_LT((momentum_after - momentum_before).norm() / momentum_before.norm(), 1e-8);
}

TEST(RigidBodyTest, ConstantYawRateTurnsByRateTimesTime) {
  for (Integrator integrator : {Integrator::kRk4, Integrator::kSemiImplicitEuler}) {
    RigidBodyParams params;
    RigidBodyState state;
    state.angular_velocity_rad_s = {0.0, 0.0, 1.0};
    for (int i = 0; i < 1000; ++i) {
      state = StepRigidBody(params, state, {}, kG, 1e-3, integrator);
    }
    const Eigen::AngleAxisd turned(state.orientation);
    EXPECT_NEAR(turned.angle(), 1.0, 1e-10);
    EXPECT_NEAR(turned.axis().z(), 1.0, 1e-10);
  }
}

TEST(RigidBodyTest, SemiImplicitEulerTurnsByTheExactRotationEitherSideOfItsSeriesCutoff) {
  // A spin about a principal axis keeps its rate, so one step turns by exactly rate * dt. The
  // step's rotation comes from a Taylor series below a half-angle of about 0.0316 rad and from
  // cos/sin above: 1 rad/s and 63 rad/s take the series at 1 ms, 64 and 100 rad/s the library.
  for (const double rate_rad_s : {1.0, 63.0, 64.0, 100.0}) {
    RigidBodyParams params;
    RigidBodyState state;
    state.angular_velocity_rad_s = {0.0, 0.0, rate_rad_s};
    const double dt_s = 1e-3;

    state = StepRigidBody(params, state, {}, kG, dt_s, Integrator::kSemiImplicitEuler);

    const double half_angle = 0.5 * rate_rad_s * dt_s;
    EXPECT_NEAR(state.orientation.w(), std::cos(half_angle), 1e-15) << rate_rad_s;
    EXPECT_NEAR(state.orientation.z(), std::sin(half_angle), 1e-15) << rate_rad_s;
    EXPECT_EQ(state.orientation.x(), 0.0) << rate_rad_s;
    EXPECT_EQ(state.orientation.y(), 0.0) << rate_rad_s;
  }
}

TEST(RigidBodyTest, BodyTorqueAcceleratesAboutItsAxis) {
  RigidBodyParams params;
  RigidBodyState state;
  Wrench wrench;
  wrench.torque_body_nm = {0.0, 0.0, 1e-3};
  for (int i = 0; i < 100; ++i) {
    state = StepRigidBody(params, state, wrench, kG, 1e-3, Integrator::kRk4);
  }
  EXPECT_NEAR(state.angular_velocity_rad_s.z(), 1e-3 / 5e-3 * 0.1, 1e-12);
}

TEST(RigidBodyTest, QuaternionStaysUnitOverOneHourAtOneKilohertz) {
  const RigidBodyParams params = AsymmetricBody();
  RigidBodyState state = SpinningState();
  double worst = 0.0;
  // An hour; a tenth of it in the sanitizer build (tests/support/long_run.h).
  for (int i = 0; i < test_support::kLongRunSteps; ++i) {
    state = StepRigidBody(params, state, {}, kG, 1e-3, Integrator::kRk4);
    worst = std::max(worst, std::abs(state.orientation.norm() - 1.0));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(RigidBodyTest, MechanicalEnergySumsAllThreeParts) {
  RigidBodyParams params;
  RigidBodyState state;
  state.position_m = {5.0, 5.0, 2.0};
  state.velocity_m_s = {1.0, 0.0, 0.0};
  state.angular_velocity_rad_s = {0.0, 0.0, 10.0};
  const double expected = 0.5 * 0.556 * 1.0 + 0.5 * 5e-3 * 100.0 + 0.556 * kG * 2.0;
  EXPECT_NEAR(MechanicalEnergy(params, state, kG), expected, 1e-12);
}

}  // namespace
}  // namespace hilrig::host
