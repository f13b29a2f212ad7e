#include "host/plant/quadrotor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/plant/grasp_contact.h"

namespace hilrig::host {
namespace {

constexpr double kDt = 1e-3;
const Eigen::Vector3d kNoForce = Eigen::Vector3d::Zero();

std::array<double, 4> Uniform(double thrust_n) { return {thrust_n, thrust_n, thrust_n, thrust_n}; }

TEST(QuadrotorTest, HoverThrustKeepsVehicleStillAtAltitude) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {1.0, -2.0, 2.0}, 0.3);
  const double hover = HoverThrustPerRotor(params);
  for (int i = 0; i < 10000; ++i) {
    state = StepQuadrotor(params, state, Uniform(hover), kNoForce, kDt);
  }
  EXPECT_LT((state.body.position_m - Eigen::Vector3d(1.0, -2.0, 2.0)).norm(), 1e-9);
  EXPECT_LT(state.body.velocity_m_s.norm(), 1e-9);
  EXPECT_LT(state.body.angular_velocity_rad_s.norm(), 1e-12);
  EXPECT_LT((state.specific_force_body_m_s2 - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-12);
  EXPECT_FALSE(state.on_ground);
  EXPECT_EQ(state.ground_impacts, 0u);
}

TEST(AdvanceQuadrotorTest, HoverInPlaceKeepsVehicleStill) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.5, 0.0, 1.0}, 0.0);
  const QuadrotorStepSize step = MakeQuadrotorStepSize(params, kDt);
  for (int i = 0; i < 1000; ++i) {
    AdvanceQuadrotor(params, state, Uniform(HoverThrustPerRotor(params)), kNoForce, step);
  }
  EXPECT_LT((state.body.position_m - Eigen::Vector3d(0.5, 0.0, 1.0)).norm(), 1e-12);
  EXPECT_LT((state.specific_force_body_m_s2 - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-12);
  EXPECT_EQ(state.integrator_accepted_substeps, 1000u);
}

// Falls at 1 m/s from just above the ground with the rotors off, stepping in place at `dt_s`
// for 0.1 s: the largest upward specific force the gear gives.
double PeakTouchDownSpecificForce(double dt_s, QuadrotorState* end = nullptr) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 0.5e-3}, 0.0);
  state.rotors.thrust_n.fill(0.0);
  state.body.velocity_m_s = {0.0, 0.0, -1.0};
  const QuadrotorStepSize step = MakeQuadrotorStepSize(params, dt_s);
  double peak = 0;
  for (int i = 0; i < int(std::lround(0.1 / dt_s)); ++i) {
    AdvanceQuadrotor(params, state, Uniform(0.0), kNoForce, step);
    peak = std::max(peak, state.specific_force_body_m_s2.z());
  }
  if (end) *end = state;
  return peak;
}

// The gear stops the descent over its own time, not one step: the accelerometer's peak (and what
// a held object presses on the pads) converges as the step shrinks, near v sqrt(k / m) + c v / m.
TEST(AdvanceQuadrotorTest, TouchDownDecelerationConvergesWithTheStep) {
  const double coarse = PeakTouchDownSpecificForce(1e-3);
  const double half = PeakTouchDownSpecificForce(5e-4);
  const double fine = PeakTouchDownSpecificForce(1.25e-4);
  EXPECT_LT(std::abs(half - fine), 0.05 * fine);
  EXPECT_LT(std::abs(coarse - fine), 0.10 * fine);
  const LandingGearParams gear;
  const double mass = QuadrotorParams().body.mass_kg;
  EXPECT_LT(fine, std::sqrt(gear.stiffness_n_per_m / mass) + gear.damping_n_s_per_m / mass);
  EXPECT_GT(fine, 0.5 * std::sqrt(gear.stiffness_n_per_m / mass));
}

TEST(AdvanceQuadrotorTest, TouchDownRecordsTheImpactAndComesToRest) {
  QuadrotorState state;
  PeakTouchDownSpecificForce(1e-3, &state);
  EXPECT_TRUE(state.on_ground);
  EXPECT_FALSE(state.gear_compressed);
  EXPECT_EQ(state.ground_impacts, 1u);
  EXPECT_NEAR(state.last_impact_speed_m_s, 1.0, 0.02);
  EXPECT_EQ(state.body.position_m.z(), 0.0);
  EXPECT_EQ(state.body.velocity_m_s.norm(), 0.0);
  // The gear pushed at most about v (sqrt(k m) + c), and the vehicle now rests on it.
  const LandingGearParams gear;
  const double mass = QuadrotorParams().body.mass_kg;
  EXPECT_GT(state.max_ground_normal_force_n, 0.5 * std::sqrt(gear.stiffness_n_per_m * mass));
  EXPECT_LT(state.max_ground_normal_force_n,
            std::sqrt(gear.stiffness_n_per_m * mass) + gear.damping_n_s_per_m);
  EXPECT_NEAR(state.ground_normal_force_n, mass * 9.81, 1e-9);
}

TEST(QuadrotorStepSizeTest, BlendIsTheRotorLagOverTheStep) {
  QuadrotorParams params;
  params.rotors.time_constant_s = 0.02;
  const QuadrotorStepSize step = MakeQuadrotorStepSize(params, 5e-3);
  EXPECT_EQ(step.dt_s, 5e-3);
  EXPECT_NEAR(step.rotor_lag_blend, 1.0 - std::exp(-0.25), 1e-15);
  params.rotors.instantaneous = true;
  EXPECT_EQ(MakeQuadrotorStepSize(params, 5e-3).rotor_lag_blend, 1.0);
}

TEST(QuadrotorStepSizeTest, RotorsMoveByTheBlendOfTheStep) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 1.0}, 0.0);
  const double hover = HoverThrustPerRotor(params);
  // The step size says the blend; a commanded jump of 1 N moves each rotor by exactly that share.
  QuadrotorStepSize step = MakeQuadrotorStepSize(params, kDt);
  step.rotor_lag_blend = 0.25;
  state = StepQuadrotor(params, state, Uniform(hover + 1.0), kNoForce, step);
  for (double thrust : state.rotors.thrust_n) EXPECT_NEAR(thrust, hover + 0.25, 1e-15);
}

TEST(QuadrotorTest, RestsOnGroundWithZeroThrust) {
  QuadrotorParams params;
  QuadrotorState state;  // default: level on the ground at the origin
  for (int i = 0; i < 1000; ++i) {
    state = StepQuadrotor(params, state, Uniform(0.0), kNoForce, kDt);
  }
  EXPECT_EQ(state.body.position_m, Eigen::Vector3d::Zero());
  EXPECT_EQ(state.body.velocity_m_s, Eigen::Vector3d::Zero());
  EXPECT_TRUE(state.on_ground);
  EXPECT_FALSE(state.airborne_once);
  EXPECT_LT((state.specific_force_body_m_s2 - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-15);
}

TEST(QuadrotorTest, StaysOnGroundWhileThrustIsBelowWeight) {
  QuadrotorParams params;
  QuadrotorState state = MakeRestingQuadrotor(params, 0.5, 0.5, 1.0);
  // Below weight, and unbalanced: the legs hold it level and in place.
  const std::array<double, 4> command = {1.3, 1.0, 1.3, 1.0};
  for (int i = 0; i < 1000; ++i) state = StepQuadrotor(params, state, command, kNoForce, kDt);
  EXPECT_EQ(state.body.position_m, Eigen::Vector3d(0.5, 0.5, 0.0));
  EXPECT_EQ(state.body.angular_velocity_rad_s, Eigen::Vector3d::Zero());
  EXPECT_TRUE(state.on_ground);
}

TEST(QuadrotorTest, TakesOffWhenThrustExceedsWeight) {
  QuadrotorParams params;
  QuadrotorState state;
  const double climb = 1.2 * HoverThrustPerRotor(params);
  for (int i = 0; i < 2000; ++i) {
    state = StepQuadrotor(params, state, Uniform(climb), kNoForce, kDt);
  }
  EXPECT_FALSE(state.on_ground);
  EXPECT_TRUE(state.airborne_once);
  EXPECT_GT(state.body.position_m.z(), 1.0);  // 0.2 g for ~2 s, minus the rotor lag
  EXPECT_GT(state.body.velocity_m_s.z(), 0.0);
  EXPECT_EQ(state.ground_impacts, 0u);
  // Thrust minus the drag of the climb, per unit mass (the thrust lag has settled by now).
  const double expected_z =
      (4.0 * climb - params.linear_drag_n_s_per_m * state.body.velocity_m_s.z()) /
      params.body.mass_kg;
  EXPECT_NEAR(state.specific_force_body_m_s2.z(), expected_z, 1e-3);
}

TEST(QuadrotorTest, FallingVehicleRecordsOneImpactWithItsSpeed) {
  QuadrotorParams params;
  params.rotors.instantaneous = true;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 1.0}, 0.0);
  int contact_steps = 0;
  for (int i = 0; i < 1000; ++i) {
    state = StepQuadrotor(params, state, Uniform(0.0), kNoForce, kDt);
    contact_steps += state.ground_contact ? 1 : 0;
  }
  EXPECT_EQ(state.ground_impacts, 1u);
  EXPECT_EQ(contact_steps, 1);
  EXPECT_TRUE(state.touched_down_after_takeoff);
  EXPECT_TRUE(state.on_ground);
  // sqrt(2 g h) = 4.43 m/s without drag; linear drag (c/m = 0.09 /s over 0.45 s) takes ~2%.
  const double free_fall_speed = std::sqrt(2.0 * 9.81 * 1.0);
  EXPECT_GT(state.last_impact_speed_m_s, 0.95 * free_fall_speed);
  EXPECT_LT(state.last_impact_speed_m_s, free_fall_speed);
  EXPECT_EQ(state.max_impact_speed_m_s, state.last_impact_speed_m_s);
}

TEST(QuadrotorTest, TouchDownStopsWithoutBounce) {
  QuadrotorParams params;
  params.rotors.instantaneous = true;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 0.2}, 0.0);
  state.body.velocity_m_s = {1.0, 0.5, 0.0};
  state.body.angular_velocity_rad_s = {0.2, -0.1, 0.3};
  for (int i = 0; i < 2000; ++i) {
    state = StepQuadrotor(params, state, Uniform(0.0), kNoForce, kDt);
  }
  EXPECT_EQ(state.body.position_m.z(), 0.0);
  EXPECT_EQ(state.body.velocity_m_s, Eigen::Vector3d::Zero());
  EXPECT_EQ(state.body.angular_velocity_rad_s, Eigen::Vector3d::Zero());
  EXPECT_EQ(state.ground_impacts, 1u);
}

TEST(QuadrotorTest, ExternalForceReachesDragTerminalVelocity) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 2.0}, 0.0);
  const Eigen::Vector3d push(0.1, 0.0, 0.0);
  const double hover = HoverThrustPerRotor(params);
  // Time constant m / c = 11 s; 120 s leaves e^-10 of the transient.
  for (int i = 0; i < 120000; ++i) state = StepQuadrotor(params, state, Uniform(hover), push, kDt);
  EXPECT_NEAR(state.body.velocity_m_s.x(), 0.1 / 0.05, 1e-3);
  EXPECT_NEAR(state.body.position_m.z(), 2.0, 1e-9);
}

TEST(QuadrotorTest, DifferentialThrustRollsTheVehicle) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 2.0}, 0.0);
  const double hover = HoverThrustPerRotor(params);
  // More thrust on the left rotors (1, 2) rolls positive about x.
  const std::array<double, 4> command = {hover - 0.01, hover + 0.01, hover + 0.01, hover - 0.01};
  for (int i = 0; i < 100; ++i) state = StepQuadrotor(params, state, command, kNoForce, kDt);
  EXPECT_GT(state.body.angular_velocity_rad_s.x(), 0.0);
  EXPECT_NEAR(state.body.angular_velocity_rad_s.y(), 0.0, 1e-12);
  EXPECT_NEAR(state.body.angular_velocity_rad_s.z(), 0.0, 1e-12);
}

// The vehicle holding a 0.5 kg ball 60 mm across, its centre about 5 cm below the body origin (a
// frame mounted under the vehicle), as the grasp contact hands it to the vehicle step.
struct HeldBall {
  Payload payload;
  double centre_below_origin_m = 0;
};

HeldBall HoldHeavyBall(const Eigen::Vector3d& vehicle_position_m) {
  GraspSceneParams scene;
  scene.object.name = "heavy_ball";
  scene.object.mass_kg = 0.5;
  scene.object.half_width_m = 0.030;
  scene.object.stiffness = 5e4;
  scene.frame.height_m = -0.05;
  scene.stand_present = false;
  GraspState grasp = InitialGraspState(scene);
  grasp.mode = GraspMode::kHeld;
  grasp.gripped = true;
  GraspVehicleSample vehicle;
  vehicle.position_m = vehicle_position_m;
  const double squeeze_rad = AngleForPadRadius(scene.frame, scene.object.half_width_m - 1e-3);
  const GraspForces forces = StepGrasp(scene, grasp, vehicle, squeeze_rad, kDt);
  EXPECT_EQ(grasp.mode, GraspMode::kHeld);
  return {{forces.payload_mass_kg, forces.payload_inertia_kg_m2},
          vehicle_position_m.z() - grasp.object_height_m};
}

// Angular acceleration of a hovering vehicle over one step whose rotors already give `thrust_n`:
// from rest about one principal axis the gyroscopic term stays zero, so the rate grows linearly.
Eigen::Vector3d AngularAccelerationFromRest(const std::array<double, 4>& thrust_n,
                                            const Payload& payload) {
  QuadrotorParams params;
  QuadrotorState state = MakeHoveringQuadrotor(params, {0.0, 0.0, 2.0}, 0.0);
  state.rotors.thrust_n = thrust_n;
  AdvanceQuadrotor(params, state, thrust_n, kNoForce, MakeQuadrotorStepSize(params, kDt), payload);
  return state.body.angular_velocity_rad_s / kDt;
}

TEST(QuadrotorTest, HeldObjectTurnsWithTheVehicleAboutItsOrigin) {
  const QuadrotorParams params;
  const HeldBall ball = HoldHeavyBall({0.0, 0.0, 2.0});
  ASSERT_NEAR(ball.centre_below_origin_m, 0.05, 1e-3);  // and the pads' shear deflection
  const double own_kg_m2 = 0.4 * 0.5 * 0.030 * 0.030;
  const double offset_kg_m2 = 0.5 * ball.centre_below_origin_m * ball.centre_below_origin_m;
  const double hover = HoverThrustPerRotor(params);
  RotorState rotors;

  // Roll: the ball's own inertia and the parallel-axis term for its 5 cm offset.
  const std::array<double, 4> roll = {hover - 0.01, hover + 0.01, hover + 0.01, hover - 0.01};
  rotors.thrust_n = roll;
  const double roll_torque_nm = RotorTorqueBody(params.rotors, rotors).x();
  const double roll_inertia_kg_m2 = params.body.inertia_kg_m2.x() + own_kg_m2 + offset_kg_m2;
  EXPECT_NEAR(AngularAccelerationFromRest(roll, ball.payload).x(),
              roll_torque_nm / roll_inertia_kg_m2, 1e-9 * roll_torque_nm / roll_inertia_kg_m2);

  // Yaw: the offset lies on the axis, so only the ball's own inertia adds.
  const std::array<double, 4> yaw = {hover - 0.01, hover - 0.01, hover + 0.01, hover + 0.01};
  rotors.thrust_n = yaw;
  const double yaw_torque_nm = RotorTorqueBody(params.rotors, rotors).z();
  const double yaw_inertia_kg_m2 = params.body.inertia_kg_m2.z() + own_kg_m2;
  ASSERT_GT(yaw_torque_nm, 0.0);
  EXPECT_NEAR(AngularAccelerationFromRest(yaw, ball.payload).z(), yaw_torque_nm / yaw_inertia_kg_m2,
              1e-9 * yaw_torque_nm / yaw_inertia_kg_m2);
}

TEST(QuadrotorTest, NoPayloadInertiaWithoutAHeldObject) {
  const QuadrotorParams params;
  const double hover = HoverThrustPerRotor(params);
  const std::array<double, 4> roll = {hover - 0.01, hover + 0.01, hover + 0.01, hover - 0.01};
  RotorState rotors;
  rotors.thrust_n = roll;
  EXPECT_NEAR(AngularAccelerationFromRest(roll, {}).x(),
              RotorTorqueBody(params.rotors, rotors).x() / params.body.inertia_kg_m2.x(), 1e-9);
}

}  // namespace
}  // namespace hilrig::host
