// Rigid-body dynamics of the vehicle: a single body with a diagonal (principal-axis) inertia,
// driven by a wrench that is held constant over one step (zero-order hold, matching a
// fixed-rate actuator update) plus gravity. Frames are those shared with the controller:
// world z up with gravity (0, 0, -g), the orientation quaternion rotates body to world (R_WB),
// the angular velocity is expressed in the body frame. The model holds no state of its own:
// the caller owns RigidBodyState and gets a new one back from every step.
#ifndef HILRIG_HOST_PLANT_RIGID_BODY_H_
#define HILRIG_HOST_PLANT_RIGID_BODY_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hilrig::host {

struct RigidBodyParams {
  double mass_kg = 0.556;
  // Principal moments in the body frame; products of inertia are neglected for the
  // symmetric X frame.
  Eigen::Vector3d inertia_kg_m2 = {3e-3, 3e-3, 5e-3};
};

struct RigidBodyState {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();   // R_WB
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();  // body frame
};

// Everything acting on the body except gravity, which the step adds itself.
struct Wrench {
  Eigen::Vector3d force_world_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_body_nm = Eigen::Vector3d::Zero();
};

enum class Integrator {
  // v += a dt, p += v_new dt, w += dw dt, q *= exp(w_new dt / 2): cheap and symplectic-ish,
  // first-order accurate.
  kSemiImplicitEuler,
  // Classic fourth-order Runge-Kutta on (p, v, q, w). With the force held constant over the
  // step the translational part is exact, so it is evaluated in closed form.
  kRk4,
};

// Advances the body by dt_s. Gravity is added inside; Euler's equations include the
// gyroscopic term w x (I w); the quaternion is renormalized every step.
RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator);

// Kinetic (translational + rotational) plus potential energy relative to z = 0.
double MechanicalEnergy(const RigidBodyParams& params, const RigidBodyState& state,
                        double gravity_m_s2);

// Angular momentum expressed in the world frame, R_WB I w: conserved without torque, which
// makes it the natural check on the rotational integrator.
Eigen::Vector3d AngularMomentumWorld(const RigidBodyParams& params, const RigidBodyState& state);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_RIGID_BODY_H_
