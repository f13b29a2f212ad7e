// The vehicle fidelity levels (vertical rail, fixed stand) and the integrator settings as the
// quadrotor plant passes them through.
#include <gtest/gtest.h>

#include <cmath>

#include "host/plant/quadrotor.h"

namespace hilrig::host {
namespace {

constexpr double kDt = 1e-3;

std::array<double, 4> Uniform(double thrust_n) { return {thrust_n, thrust_n, thrust_n, thrust_n}; }

QuadrotorParams Vertical() {
  QuadrotorParams params;
  params.fidelity = VehicleFidelity::kVertical1Dof;
  params.rotors.instantaneous = true;
  return params;
}

TEST(QuadrotorFidelityTest, VerticalRailClimbsWithTheThrustSurplus) {
  const QuadrotorParams params = Vertical();
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.5, -1.0, 1.0}, 0.4);
  const double thrust = 1.1 * HoverThrustPerRotor(params);
  double last_start_vz = 0.0;
  for (int i = 0; i < 1000; ++i) {
    last_start_vz = state.body.velocity_m_s.z();
    state = StepQuadrotor(params, state, Uniform(thrust), Eigen::Vector3d::Zero(), kDt);
  }
  // 0.1 g up for 1 s; drag c/m = 0.09 /s removes ~3 % of the climb.
  const double no_drag = 0.5 * 0.1 * 9.81;
  EXPECT_GT(state.body.position_m.z() - 1.0, 0.95 * no_drag);
  EXPECT_LT(state.body.position_m.z() - 1.0, no_drag);
  EXPECT_NEAR(state.specific_force_body_m_s2.z(),
              (4 * thrust - 0.05 * last_start_vz) / params.body.mass_kg, 1e-12);
}

TEST(QuadrotorFidelityTest, VerticalRailAllowsNoHorizontalMotionOrRotation) {
  const QuadrotorParams params = Vertical();
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.5, -1.0, 1.0}, 0.4);
  // Start tilted and spinning, push sideways, command a roll torque: the rail takes it all.
  state.body.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                                              Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  state.body.angular_velocity_rad_s = {1.0, 2.0, 0.5};
  state.body.velocity_m_s = {1.0, 1.0, 0.0};
  const double hover = HoverThrustPerRotor(params);
  const std::array<double, 4> rolling = {hover - 0.2, hover + 0.2, hover + 0.2, hover - 0.2};
  for (int i = 0; i < 2000; ++i) {
    state = StepQuadrotor(params, state, rolling, {3.0, -2.0, 0.0}, kDt);
  }
  EXPECT_EQ(state.body.position_m.x(), 0.5);
  EXPECT_EQ(state.body.position_m.y(), -1.0);
  EXPECT_EQ(state.body.velocity_m_s.head<2>(), Eigen::Vector2d::Zero());
  EXPECT_EQ(state.body.angular_velocity_rad_s, Eigen::Vector3d::Zero());
  // Level with the yaw it had.
  const Eigen::Vector3d body_z = state.body.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(body_z.z(), 1.0, 1e-15);
  const Eigen::Vector3d body_x = state.body.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(body_x.y(), body_x.x()), 0.4, 1e-12);
  // Collective equals the weight, so it holds its altitude.
  EXPECT_NEAR(state.body.position_m.z(), 1.0, 1e-9);
}

TEST(QuadrotorFidelityTest, VerticalRailLandsOnTheGroundAsTheFullModelDoes) {
  const QuadrotorParams params = Vertical();
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 0.5}, 0.0);
  for (int i = 0; i < 1000; ++i) {
    state = StepQuadrotor(params, state, Uniform(0.0), Eigen::Vector3d::Zero(), kDt);
  }
  EXPECT_TRUE(state.on_ground);
  EXPECT_EQ(state.ground_impacts, 1u);
  // sqrt(2 g h) = 3.13 m/s, a little less with drag.
  EXPECT_GT(state.last_impact_speed_m_s, 0.97 * std::sqrt(2 * 9.81 * 0.5));
  EXPECT_LT(state.last_impact_speed_m_s, std::sqrt(2 * 9.81 * 0.5));
}

QuadrotorParams Stand() {
  QuadrotorParams params;
  params.fidelity = VehicleFidelity::kFixedStand;
  return params;
}

TEST(QuadrotorFidelityTest, FixedStandKeepsThePoseWhileRotorsSpin) {
  const QuadrotorParams params = Stand();
  QuadrotorState state = MakeRestingQuadrotor(params, 0.2, 0.3, 1.0);
  state.body.position_m.z() = 0.8;  // a stand 0.8 m tall
  const QuadrotorState start = state;
  const double climb = 2.0 * HoverThrustPerRotor(params);
  for (int i = 0; i < 1000; ++i) {
    state = StepQuadrotor(params, state, Uniform(climb), {5.0, 0.0, 5.0}, kDt);
  }
  EXPECT_EQ(state.body.position_m, start.body.position_m);
  EXPECT_EQ(state.body.orientation.coeffs(), start.body.orientation.coeffs());
  EXPECT_EQ(state.body.velocity_m_s, Eigen::Vector3d::Zero());
  // 1 s is 33 rotor time constants: the thrust has reached the command.
  EXPECT_NEAR(state.rotors.thrust_n[0], climb, 1e-9);
  EXPECT_EQ(state.ground_impacts, 0u);
}

TEST(QuadrotorFidelityTest, FixedStandAccelerometerReadsTheStandHoldingItAgainstGravity) {
  const QuadrotorParams params = Stand();
  QuadrotorState state = MakeRestingQuadrotor(params, 0.0, 0.0, 0.0);
  // Bolted at 30 degrees of pitch: gravity's reaction splits between body x and z.
  state.body.orientation = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitY());
  state = StepQuadrotor(params, state, Uniform(1.0), Eigen::Vector3d::Zero(), kDt);
  EXPECT_NEAR(state.specific_force_body_m_s2.x(), -9.81 * std::sin(0.5236), 1e-12);
  EXPECT_NEAR(state.specific_force_body_m_s2.y(), 0.0, 1e-12);
  EXPECT_NEAR(state.specific_force_body_m_s2.z(), 9.81 * std::cos(0.5236), 1e-12);
}

TEST(QuadrotorFidelityTest, AirborneStepsCountIntegratorSubsteps) {
  QuadrotorParams params;
  params.integrator = Integrator::kDormandPrince;
  params.integrator_tolerance = 1e-9;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 2.0}, 0.0);
  const double hover = HoverThrustPerRotor(params);
  const std::array<double, 4> rolling = {hover - 0.05, hover + 0.05, hover + 0.05, hover - 0.05};
  // 0.1 s steps of a rolling vehicle: more than one substep each.
  for (int i = 0; i < 5; ++i) {
    state = StepQuadrotor(params, state, rolling, Eigen::Vector3d::Zero(), 0.1);
  }
  EXPECT_GT(state.integrator_accepted_substeps, 5u);
  EXPECT_EQ(state.integrator_failures, 0u);
}

TEST(QuadrotorFidelityTest, UnusableToleranceIsCountedAsAFailure) {
  QuadrotorParams params;
  params.integrator = Integrator::kDormandPrince;
  params.integrator_tolerance = std::nan("");
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 2.0}, 0.0);
  state = StepQuadrotor(params, state, Uniform(1.0), Eigen::Vector3d::Zero(), kDt);
  EXPECT_EQ(state.integrator_failures, 1u);
  EXPECT_TRUE(state.body.position_m.allFinite());
}

TEST(QuadrotorFidelityTest, EveryIntegratorHoldsHover) {
  for (Integrator integrator : {Integrator::kSemiImplicitEuler, Integrator::kMidpoint,
                                Integrator::kRk4, Integrator::kDormandPrince}) {
    QuadrotorParams params;
    params.integrator = integrator;
    QuadrotorState state = MakeHoveringQuadrotor(params, {1.0, -2.0, 2.0}, 0.3);
    const double hover = HoverThrustPerRotor(params);
    for (int i = 0; i < 10000; ++i) {
      state = StepQuadrotor(params, state, Uniform(hover), Eigen::Vector3d::Zero(), kDt);
    }
    EXPECT_LT((state.body.position_m - Eigen::Vector3d(1.0, -2.0, 2.0)).norm(), 1e-9)
        << IntegratorName(integrator);
    EXPECT_EQ(state.integrator_accepted_substeps, 10000u) << IntegratorName(integrator);
  }
}

}  // namespace
}  // namespace hilrig::host
