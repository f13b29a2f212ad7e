#include "host/plant/quadrotor.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hilrig::host {
namespace {

Eigen::Quaterniond YawQuaternion(double yaw_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()));
}

// The body as the vertical rail holds it: yaw kept, roll and pitch removed, only vertical
// velocity, no rotation.
RigidBodyState OnVerticalRail(const RigidBodyState& body) {
  RigidBodyState railed = body;
  const Eigen::Matrix3d r_wb = body.orientation.toRotationMatrix();
  railed.orientation = YawQuaternion(std::atan2(r_wb(1, 0), r_wb(0, 0)));
  railed.velocity_m_s.head<2>().setZero();
  railed.angular_velocity_rad_s.setZero();
  return railed;
}

// Bolted down: the pose stays, and the accelerometer reads the stand holding it against gravity.
void HoldOnStand(const QuadrotorParams& params, QuadrotorState& next) {
  next.body.velocity_m_s.setZero();
  next.body.angular_velocity_rad_s.setZero();
  next.specific_force_body_m_s2 =
      next.body.orientation.conjugate() * Eigen::Vector3d(0.0, 0.0, params.gravity_m_s2);
}

}  // namespace

QuadrotorStepSize MakeQuadrotorStepSize(const QuadrotorParams& params, double dt_s) {
  return {dt_s, RotorLagBlend(params.rotors, dt_s)};
}

QuadrotorState StepQuadrotor(const QuadrotorParams& params, const QuadrotorState& state,
                             const std::array<double, kRotorCount>& commanded_thrust_n,
                             const Eigen::Vector3d& external_force_world_n, double dt_s,
                             const Payload& payload) {
  return StepQuadrotor(params, state, commanded_thrust_n, external_force_world_n,
                       MakeQuadrotorStepSize(params, dt_s), payload);
}

QuadrotorState StepQuadrotor(const QuadrotorParams& params, const QuadrotorState& state,
                             const std::array<double, kRotorCount>& commanded_thrust_n,
                             const Eigen::Vector3d& external_force_world_n,
                             const QuadrotorStepSize& step, const Payload& payload) {
  QuadrotorState next = state;
  AdvanceQuadrotor(params, next, commanded_thrust_n, external_force_world_n, step, payload);
  return next;
}

void AdvanceQuadrotor(const QuadrotorParams& params, QuadrotorState& state,
                      const std::array<double, kRotorCount>& commanded_thrust_n,
                      const Eigen::Vector3d& external_force_world_n, const QuadrotorStepSize& step,
                      const Payload& payload) {
  const double dt_s = step.dt_s;
  state.ground_contact = false;
  state.rotors =
      StepRotorsWithBlend(params.rotors, state.rotors, commanded_thrust_n, step.rotor_lag_blend);
  if (params.fidelity == VehicleFidelity::kFixedStand) {
    HoldOnStand(params, state);
    return;
  }
  const bool on_rail = params.fidelity == VehicleFidelity::kVertical1Dof;
  if (on_rail) state.body = OnVerticalRail(state.body);
  RigidBodyState& body_state = state.body;

  RigidBodyParams body = params.body;
  if (payload.mass_kg > 0 && std::isfinite(payload.mass_kg)) {
    body.mass_kg += payload.mass_kg;
    if (payload.inertia_kg_m2.allFinite() && payload.inertia_kg_m2.minCoeff() >= 0) {
      body.inertia_kg_m2 += payload.inertia_kg_m2;
    }
  }
  const double mass = body.mass_kg;
  const double g = params.gravity_m_s2;
  const Eigen::Matrix3d r_wb = body_state.orientation.toRotationMatrix();
  const double collective = CollectiveThrust(state.rotors);
  Eigen::Vector3d non_thrust_force =
      external_force_world_n - params.linear_drag_n_s_per_m * body_state.velocity_m_s;
  if (on_rail) non_thrust_force.head<2>().setZero();  // the rail takes horizontal loads

  Wrench wrench;
  wrench.force_world_n = r_wb.col(2) * collective + non_thrust_force;
  wrench.torque_body_nm =
      on_rail ? Eigen::Vector3d::Zero() : RotorTorqueBody(params.rotors, state.rotors);

  if (state.on_ground && wrench.force_world_n.z() <= mass * g) {
    body_state.position_m.z() = 0.0;
    body_state.velocity_m_s.setZero();
    body_state.angular_velocity_rad_s.setZero();
    state.specific_force_body_m_s2 = r_wb.transpose() * Eigen::Vector3d(0.0, 0.0, g);
    return;
  }

  state.on_ground = false;
  state.airborne_once = true;
  // The touch-down below needs the velocity the step started with; the step overwrites the body.
  const Eigen::Vector3d start_velocity_m_s = body_state.velocity_m_s;
  RigidBodyIntegratorOptions options;
  options.tolerance = params.integrator_tolerance;
  IntegratorStats stats;
  body_state = StepRigidBody(body, body_state, wrench, g, dt_s, params.integrator, options, &stats);
  state.integrator_accepted_substeps += stats.accepted_substeps;
  state.integrator_rejected_substeps += stats.rejected_substeps;
  state.integrator_failures += stats.failed ? 1 : 0;
  // Thrust written directly in the body frame so that hover reads exactly (0, 0, T/m).
  state.specific_force_body_m_s2 = (r_wb.transpose() * non_thrust_force) / mass;
  state.specific_force_body_m_s2.z() += collective / mass;

  if (body_state.position_m.z() < 0.0) {
    const double impact_speed = std::max(0.0, -body_state.velocity_m_s.z());
    // The ground removed the whole velocity within this step; the accelerometer sees that
    // average deceleration as a spike, as a real one would (smeared over one tick).
    const Eigen::Vector3d accel_world = -start_velocity_m_s / dt_s + Eigen::Vector3d(0.0, 0.0, g);
    state.specific_force_body_m_s2 = body_state.orientation.conjugate() * accel_world;
    body_state.position_m.z() = 0.0;
    body_state.velocity_m_s.setZero();
    body_state.angular_velocity_rad_s.setZero();
    state.on_ground = true;
    state.ground_contact = true;
    state.touched_down_after_takeoff = true;
    ++state.ground_impacts;
    state.last_impact_speed_m_s = impact_speed;
    state.max_impact_speed_m_s = std::max(state.max_impact_speed_m_s, impact_speed);
  }
}

double HoverThrustPerRotor(const QuadrotorParams& params) {
  return params.body.mass_kg * params.gravity_m_s2 / kRotorCount;
}

QuadrotorState MakeRestingQuadrotor(const QuadrotorParams& params, double x_m, double y_m,
                                    double yaw_rad) {
  QuadrotorState state;
  state.body.position_m = {x_m, y_m, 0.0};
  state.body.orientation = YawQuaternion(yaw_rad);
  state.specific_force_body_m_s2 = {0.0, 0.0, params.gravity_m_s2};
  return state;
}

QuadrotorState MakeHoveringQuadrotor(const QuadrotorParams& params,
                                     const Eigen::Vector3d& position_m, double yaw_rad) {
  QuadrotorState state;
  state.body.position_m = position_m;
  state.body.orientation = YawQuaternion(yaw_rad);
  state.rotors.thrust_n.fill(HoverThrustPerRotor(params));
  state.on_ground = false;
  state.airborne_once = true;
  state.specific_force_body_m_s2 = {0.0, 0.0, params.gravity_m_s2};
  return state;
}

}  // namespace hilrig::host
