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

// The gear's force on a body whose origin is below the ground, held over a step of dt_s with the
// other forces `other_world_n` (gravity included) on `mass_kg`. Linearly implicit: the normal
// force is -k z - c v_z at the end-of-step velocity v + dt (F + N) / m and position z + dt v_end
// it produces, so it cannot overshoot into a pull or an oscillation however stiff the gear or
// long the step; it never pulls. The horizontal hold is -c v_h at the end of the step, at most
// friction x N. O(1), no allocation.
Eigen::Vector3d GearForceWorld(const LandingGearParams& gear, const RigidBodyState& body,
                               const Eigen::Vector3d& other_world_n, double mass_kg, double dt_s) {
  const double z = body.position_m.z();
  if (!(z < 0.0)) return Eigen::Vector3d::Zero();
  const double k = gear.stiffness_n_per_m;
  const double c = gear.damping_n_s_per_m;
  const double velocity_gain = c + k * dt_s;  // dN / d(v_end)
  const double free_end_speed = body.velocity_m_s.z() + dt_s * other_world_n.z() / mass_kg;
  const double normal = std::max(
      0.0, -(k * z + velocity_gain * free_end_speed) / (1.0 + velocity_gain * dt_s / mass_kg));
  const Eigen::Vector2d free_end_velocity =
      body.velocity_m_s.head<2>() + dt_s * other_world_n.head<2>() / mass_kg;
  Eigen::Vector2d hold = -c * free_end_velocity / (1.0 + c * dt_s / mass_kg);
  const double hold_limit = gear.friction * normal;
  if (hold.norm() > hold_limit) hold *= hold_limit / hold.norm();
  return {hold.x(), hold.y(), normal};
}

// Back at rest on the ground: z = 0, no motion (the gear gives its compression back).
void ComeToRest(RigidBodyState& body) {
  body.position_m.z() = 0.0;
  body.velocity_m_s.setZero();
  body.angular_velocity_rad_s.setZero();
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

  const bool rotors_lift = wrench.force_world_n.z() > mass * g;
  if (state.on_ground && !rotors_lift) {
    ComeToRest(body_state);
    state.specific_force_body_m_s2 = r_wb.transpose() * Eigen::Vector3d(0.0, 0.0, g);
    state.ground_normal_force_n = mass * g - wrench.force_world_n.z();
    state.max_ground_normal_force_n =
        std::max(state.max_ground_normal_force_n, state.ground_normal_force_n);
    return;
  }

  state.on_ground = false;
  state.airborne_once = true;
  Eigen::Vector3d gear_force_world_n = Eigen::Vector3d::Zero();
  if (state.gear_compressed) {
    gear_force_world_n =
        GearForceWorld(params.landing_gear, body_state,
                       wrench.force_world_n - Eigen::Vector3d(0.0, 0.0, mass * g), mass, dt_s);
    if (on_rail) gear_force_world_n.head<2>().setZero();
  }
  wrench.force_world_n += gear_force_world_n;
  non_thrust_force += gear_force_world_n;
  state.ground_normal_force_n = gear_force_world_n.z();
  state.max_ground_normal_force_n =
      std::max(state.max_ground_normal_force_n, state.ground_normal_force_n);

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

  const bool below_ground = body_state.position_m.z() < 0.0;
  if (!state.gear_compressed && below_ground) {
    const double impact_speed = std::max(0.0, -body_state.velocity_m_s.z());
    state.gear_compressed = true;
    state.ground_contact = true;
    state.touched_down_after_takeoff = true;
    ++state.ground_impacts;
    state.last_impact_speed_m_s = impact_speed;
    state.max_impact_speed_m_s = std::max(state.max_impact_speed_m_s, impact_speed);
  } else if (state.gear_compressed && !below_ground) {
    state.gear_compressed = false;  // lifted off before the gear stopped it
  } else if (state.gear_compressed && body_state.velocity_m_s.z() >= 0.0 && !rotors_lift) {
    ComeToRest(body_state);  // the gear has stopped the descent and does not spring back
    state.gear_compressed = false;
    state.on_ground = true;
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
