// Rigid-body dynamics of the vehicle: a single body with a diagonal (principal-axis) inertia,
// driven by a wrench that is held constant over one step (zero-order hold, matching a
// fixed-rate actuator update) plus gravity. Frames are those shared with the controller:
// world z up with gravity (0, 0, -g), the orientation quaternion rotates body to world (R_WB),
// the angular velocity is expressed in the body frame. The model holds no state of its own:
// the caller owns RigidBodyState and gets a new one back from every step. Four integrators trade
// cost for accuracy and stability (semi-implicit Euler, midpoint RK2, RK4, adaptive
// Dormand-Prince RK5(4)); all of them advance exactly the requested dt and allocate nothing.
#ifndef HILRIG_HOST_PLANT_RIGID_BODY_H_
#define HILRIG_HOST_PLANT_RIGID_BODY_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

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
  // A linear spring-damper from the body origin to a world anchor. Unlike force_world_n it is
  // not held over the step but evaluated at every stage of the integrator, the way a stiff
  // attachment (tether, test-stand spring) acts between samples; it is what the integrators'
  // stability limits are measured on. Zero stiffness and damping (the default) turn it off.
  Eigen::Vector3d spring_anchor_world_m = Eigen::Vector3d::Zero();
  double spring_stiffness_n_per_m = 0.0;
  double spring_damping_n_s_per_m = 0.0;
};

enum class Integrator {
  // v += a dt, p += v_new dt (symplectic Euler); the body rate by the implicit midpoint rule on
  // Euler's equations (a fixed-point iteration, Newton where it contracts too slowly),
  // q *= exp(w_mean dt / 2) with the step's mean rate. A torque-free body keeps its rotational
  // energy and the magnitude of its angular momentum |L| (not L's direction) to the solve's
  // tolerance at every step the body turns less than kMaxRotationPerStepRad (an explicit
  // gyroscopic term would gain energy every step and tumble to NaN). First-order accurate, from
  // the translation.
  kSemiImplicitEuler,
  // Classic fourth-order Runge-Kutta on (p, v, q, w). With the force held constant over the
  // step the translational part is exact, so it is evaluated in closed form.
  kRk4,
  // Explicit second-order Runge-Kutta (midpoint rule): two derivative evaluations per step.
  kMidpoint,
  // Adaptive embedded Runge-Kutta 5(4) of Dormand and Prince (1980) with FSAL: substeps inside
  // dt under error control, so the cost follows how hard the motion is.
  kDormandPrince,
};

// The largest rotation |w| h per step that a fixed-step integrator resolves. Past one radian a step
// spans more than a sixth of a turn: the explicit Runge-Kutta rules' error terms in (|w| h)^k are
// no longer small (RK4 is unstable on a rotation past 2.83), and the implicit rate rule's answer,
// though finite, is not the motion. A run stops there rather than carry finite nonsense.
inline constexpr double kMaxRotationPerStepRad = 1.0;
// kMaxRotationPerStepRad for a fixed-step integrator; nullopt for the adaptive one, which
// subdivides its step instead. Cannot fail.
inline std::optional<double> MaxRotationPerStepRad(Integrator integrator) {
  if (integrator == Integrator::kDormandPrince) return std::nullopt;
  return kMaxRotationPerStepRad;
}

// Settings of the adaptive integrator; the fixed-step ones ignore them.
struct RigidBodyIntegratorOptions {
  // Per component, the error of a substep must stay below tolerance * (1 + |y|): the same
  // number is the relative tolerance and the absolute floor in SI units. Must be in (0, 1).
  double tolerance = 1e-6;
  double safety_factor = 0.9;  // aim a bit below the tolerance so few substeps are rejected
  double min_growth = 0.2;     // a substep shrinks by at most 5x after a rejection ...
  double max_growth = 5.0;     // ... and grows by at most 5x after an acceptance
  // Bounds the work of one call: a motion that needs more substeps is reported as a failure
  // instead of hanging the run.
  std::uint32_t max_substeps = 100000;
};

// What one call did, for a caller that wants to report it. Fixed-step integrators count one
// accepted substep per call.
struct IntegratorStats {
  std::uint32_t accepted_substeps = 0;
  std::uint32_t rejected_substeps = 0;
  // The step could not be taken: dt or the tolerance was not a usable number, or the adaptive
  // integrator ran out of substeps. With bad input the state comes back unchanged; when the
  // integrator gives up it comes back non-finite, which callers already treat as instability.
  bool failed = false;
};

// Advances the body by dt_s. Gravity is added inside; Euler's equations include the
// gyroscopic term w x (I w); the quaternion is integrated as raw coefficients of
// dq/dt = q (0, w) / 2 and renormalized after every (accepted sub)step. A dt_s that is not a
// positive finite number returns the state unchanged (and flags it in `stats`).
RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator);
// The same with the adaptive integrator's settings; `stats`, when given, receives what the
// call did (it is overwritten, not accumulated).
RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator, const RigidBodyIntegratorOptions& options,
                             IntegratorStats* stats = nullptr);

// Display name of an integrator, for reports.
const char* IntegratorName(Integrator integrator);

// Kinetic (translational + rotational) plus potential energy relative to z = 0.
double MechanicalEnergy(const RigidBodyParams& params, const RigidBodyState& state,
                        double gravity_m_s2);

// Angular momentum expressed in the world frame, R_WB I w: conserved without torque, which
// makes it the natural check on the rotational integrator.
Eigen::Vector3d AngularMomentumWorld(const RigidBodyParams& params, const RigidBodyState& state);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_RIGID_BODY_H_
