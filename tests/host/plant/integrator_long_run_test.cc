// One simulated hour at 1 kHz: what the integrators conserve (quaternion norm, energy, world
// angular momentum of a torque-free tumble) and that a vehicle held exactly at hover does not
// creep. The bounds are the measured values (stated per test) with some headroom.
#include <gtest/gtest.h>

#include <cmath>

#include "host/plant/quadrotor.h"
#include "host/plant/rigid_body.h"

namespace hilrig::host {
namespace {

constexpr int kHourAtOneKilohertz = 3'600'000;
constexpr double kDt = 1e-3;

struct TumbleHour {
  double worst_quaternion_norm_error = 0;
  double worst_energy_drift = 0;    // relative to the start
  double worst_momentum_drift = 0;  // |L - L0| / |L0|
};

// Torque-free, all moments distinct, spinning near the unstable middle axis so the body really
// tumbles (the rate vector wanders over the whole polhode).
TumbleHour RunTumbleHour() {
  RigidBodyParams params;
  params.inertia_kg_m2 = {2e-3, 3e-3, 5e-3};
  RigidBodyState state;
  state.angular_velocity_rad_s = {0.3, 3.0, 0.2};
  const double energy0 = MechanicalEnergy(params, state, 0.0);
  const Eigen::Vector3d momentum0 = AngularMomentumWorld(params, state);
  TumbleHour hour;
  for (int i = 0; i < kHourAtOneKilohertz; ++i) {
    state = StepRigidBody(params, state, {}, 0.0, kDt, Integrator::kRk4);
    hour.worst_quaternion_norm_error =
        std::max(hour.worst_quaternion_norm_error, std::abs(state.orientation.norm() - 1.0));
    if (i % 100 == 0) {
      hour.worst_energy_drift = std::max(
          hour.worst_energy_drift, std::abs(MechanicalEnergy(params, state, 0.0) / energy0 - 1));
      hour.worst_momentum_drift =
          std::max(hour.worst_momentum_drift,
                   (AngularMomentumWorld(params, state) - momentum0).norm() / momentum0.norm());
    }
  }
  return hour;
}

class TumbleHourTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { hour_ = RunTumbleHour(); }
  static TumbleHour hour_;
};
TumbleHour TumbleHourTest::hour_;

TEST_F(TumbleHourTest, QuaternionNormStaysWithinOneEMinus12) {
  EXPECT_LT(hour_.worst_quaternion_norm_error, 1e-12);
}

TEST_F(TumbleHourTest, EnergyDriftStaysBounded) {
  // Measured 2.0e-13 over the hour (RK4's own dissipation, O(h^6) per step, is below the
  // round-off at this rate).
  EXPECT_LT(hour_.worst_energy_drift, 1e-12);
}

TEST_F(TumbleHourTest, WorldAngularMomentumDriftStaysBounded) {
  // Measured 1.1e-12 over the hour.
  EXPECT_LT(hour_.worst_momentum_drift, 5e-12);
}

struct HoverHour {
  double error_at_half_hour_m = 0;
  double error_at_hour_m = 0;
};

// Rotors spun up to exactly the weight, no controller, no drag-free shortcut: only the
// integrator can move it.
HoverHour RunHoverHour(Integrator integrator) {
  QuadrotorParams params;
  params.integrator = integrator;
  const Eigen::Vector3d start(1.0, -2.0, 2.0);
  QuadrotorState state = MakeHoveringQuadrotor(params, start, 0.3);
  const double hover = HoverThrustPerRotor(params);
  const std::array<double, kRotorCount> thrust = {hover, hover, hover, hover};
  HoverHour hour;
  for (int i = 0; i < kHourAtOneKilohertz; ++i) {
    state = StepQuadrotor(params, state, thrust, Eigen::Vector3d::Zero(), kDt);
    if (i + 1 == kHourAtOneKilohertz / 2) {
      hour.error_at_half_hour_m = (state.body.position_m - start).norm();
    }
  }
  hour.error_at_hour_m = (state.body.position_m - start).norm();
  EXPECT_FALSE(state.on_ground);
  return hour;
}

TEST(HoverHourTest, SemiImplicitEulerHoldsPositionForAnHour) {
  const HoverHour hour = RunHoverHour(Integrator::kSemiImplicitEuler);
  // Measured exactly 0 at 30 and at 60 min: thrust and weight cancel to the bit, and the
  // integrator adds nothing of its own.
  EXPECT_LT(hour.error_at_hour_m, 1e-12);
  EXPECT_LE(hour.error_at_hour_m, hour.error_at_half_hour_m + 1e-15);
}

TEST(HoverHourTest, Rk4HoldsPositionForAnHour) {
  const HoverHour hour = RunHoverHour(Integrator::kRk4);
  // Measured exactly 0, as with semi-implicit Euler.
  EXPECT_LT(hour.error_at_hour_m, 1e-12);
  EXPECT_LE(hour.error_at_hour_m, hour.error_at_half_hour_m + 1e-15);
}

}  // namespace
}  // namespace hilrig::host
