// The vehicle plant: rigid body + four lagged rotors + linear aerodynamic drag + a flat ground
// at z = 0. Per step the rotors are advanced first and their new thrusts, the drag of the current
// velocity and the external force (e.g. the gripper's contact with an object) are held constant
// over the step (zero-order hold), evaluated at the attitude at the start of the step.
//
// Ground model (the landing gear as a spring-damper, not a contact simulation of the legs):
// - Resting: while on the ground and the net upward force (thrust, drag, external) does not
//   exceed the weight, the vehicle sits still at z = 0: the normal force and static friction of
//   the legs cancel everything else, rotor torques do not tilt it, velocities are zero.
// - Take-off: as soon as the net upward force exceeds the weight the body integrates freely.
// - Touch-down: a step that ends below z = 0 after being clear of the ground records the impact
//   (count, downward speed at that step's end, `ground_contact` for that one step). From then on,
//   while z < 0, the gear pushes up with N = max(0, -k z - c v_z) and the ground holds the
//   horizontal motion with -c v_h, at most friction x N; both act at the body origin (no torque).
//   N is solved linearly implicitly over the step (with the end-of-step velocity and position
//   it produces), so any k, c and step are stable and the force converges as the step shrinks:
//   the deceleration, and with it what a held object presses on the pads, is that of the gear,
//   about v_impact sqrt(k / m), not the whole velocity removed in one step. The gear does not
//   spring back: once it stops compressing (v_z >= 0) without the rotors lifting the vehicle, the
//   vehicle is at rest again at z = 0 with all velocity and angular rate removed (no bounce; the
//   compression, v_impact / sqrt(k / m) at most, is given back in that step). Touching down after
//   any time in the air, gentle landings included, counts; checks decide by the impact speed
//   what was a crash.
//
// Fidelity levels reduce the motion while the rotors and the accelerometer's view stay real:
// kVertical1Dof rides a frictionless vertical rail (level, yaw fixed, no rotation; the rail takes
// horizontal loads and rotor torques), kFixedStand is bolted to a stand where it starts (nothing
// moves; the specific force is the stand's reaction to gravity).
#ifndef HILRIG_HOST_PLANT_QUADROTOR_H_
#define HILRIG_HOST_PLANT_QUADROTOR_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "host/plant/rigid_body.h"
#include "host/plant/rotors.h"

namespace hilrig::host {

// Mirrors proto VehicleFidelity.
enum class VehicleFidelity {
  kFull6Dof,
  kVertical1Dof,  // altitude only: level, no horizontal motion, no rotation
  kFixedStand,    // bolted to a test stand: nothing moves, rotors and sensors run
};

// The legs' compliance at touch-down (see the ground model above). The defaults are a light
// carbon undercarriage: about 1 mm of sag under the default 0.556 kg, damping ratio 0.7.
struct LandingGearParams {
  double stiffness_n_per_m = 1.0e4;
  double damping_n_s_per_m = 104.0;
  double friction = 0.5;  // horizontal hold at most this times the normal force
};

struct QuadrotorParams {
  RigidBodyParams body;
  LandingGearParams landing_gear;
  RotorParams rotors;
  double linear_drag_n_s_per_m = 0.05;  // F_drag = -c v, world frame, isotropic
  double gravity_m_s2 = 9.81;
  Integrator integrator = Integrator::kRk4;
  // Error tolerance of Integrator::kDormandPrince per step (see RigidBodyIntegratorOptions).
  double integrator_tolerance = 1e-6;
  VehicleFidelity fidelity = VehicleFidelity::kFull6Dof;
};

struct QuadrotorState {
  RigidBodyState body;
  RotorState rotors;
  bool on_ground = true;
  bool airborne_once = false;  // has been off the ground at some point
  // True only for the step in which the vehicle touched down.
  bool ground_contact = false;
  // The gear is compressing after a touch-down (z < 0), until the vehicle rests or lifts off.
  bool gear_compressed = false;
  // The ground's push in the last step: the gear's while it stops a touch-down, weight less thrust
  // at rest, 0 in the air; and its largest so far.
  double ground_normal_force_n = 0.0;
  double max_ground_normal_force_n = 0.0;
  // Touched the ground after having been airborne; stays true once set.
  bool touched_down_after_takeoff = false;
  std::uint32_t ground_impacts = 0;
  double last_impact_speed_m_s = 0.0;  // downward speed at the last touch-down, >= 0
  double max_impact_speed_m_s = 0.0;   // largest of all touch-downs
  // Non-gravitational acceleration in the body frame, averaged over the last step: what an
  // accelerometer measures. Resting level on the ground it is (0, 0, +g).
  Eigen::Vector3d specific_force_body_m_s2 = {0.0, 0.0, 9.81};
  // Integrator work since the start, for reports: substeps taken and rejected (fixed-step
  // integrators take one per airborne step), and steps that could not be taken at all.
  std::uint64_t integrator_accepted_substeps = 0;
  std::uint64_t integrator_rejected_substeps = 0;
  std::uint64_t integrator_failures = 0;
};

// A body held rigidly by the vehicle for one step (a grasped object). Its mass adds to the
// vehicle's mass and weight as if at the body origin; its principal moments about the body origin
// (body axes, the parallel-axis term for its offset included) add to the vehicle's inertia. The
// vehicle still turns about its own origin: the shift of the combined centre of mass, and the
// gravity torque about it when tilted, are left out (a few mm for the shipped grasps).
struct Payload {
  double mass_kg = 0.0;
  Eigen::Vector3d inertia_kg_m2 = Eigen::Vector3d::Zero();
};

QuadrotorState StepQuadrotor(const QuadrotorParams& params, const QuadrotorState& state,
                             const std::array<double, kRotorCount>& commanded_thrust_n,
                             const Eigen::Vector3d& external_force_world_n, double dt_s,
                             const Payload& payload = {});

// A step size with what depends only on it and the params (the rotors' lag blend, an expm1):
// a caller with a fixed dt makes it once and passes it to every step instead of dt_s.
struct QuadrotorStepSize {
  double dt_s = 0.0;
  double rotor_lag_blend = 1.0;  // RotorLagBlend(params.rotors, dt_s)
};
QuadrotorStepSize MakeQuadrotorStepSize(const QuadrotorParams& params, double dt_s);
// The same step as above; `step` must have been made from these params.
QuadrotorState StepQuadrotor(const QuadrotorParams& params, const QuadrotorState& state,
                             const std::array<double, kRotorCount>& commanded_thrust_n,
                             const Eigen::Vector3d& external_force_world_n,
                             const QuadrotorStepSize& step, const Payload& payload = {});
// The same step in place: `state` becomes the next state. A caller that keeps the state and
// steps it every tick saves the two copies of the whole state that a step by value costs.
void AdvanceQuadrotor(const QuadrotorParams& params, QuadrotorState& state,
                      const std::array<double, kRotorCount>& commanded_thrust_n,
                      const Eigen::Vector3d& external_force_world_n, const QuadrotorStepSize& step,
                      const Payload& payload = {});

// m g / 4: the per-rotor thrust that holds a level vehicle still.
double HoverThrustPerRotor(const QuadrotorParams& params);

// Initial states consistent with params (gravity in the specific force, rotors spun up for
// hover). The resting one puts the vehicle level on the ground at (x, y, 0) with the given yaw.
QuadrotorState MakeRestingQuadrotor(const QuadrotorParams& params, double x_m, double y_m,
                                    double yaw_rad);
QuadrotorState MakeHoveringQuadrotor(const QuadrotorParams& params,
                                     const Eigen::Vector3d& position_m, double yaw_rad);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_QUADROTOR_H_
