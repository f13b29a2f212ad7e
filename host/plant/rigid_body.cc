#include "host/plant/rigid_body.h"

#include <cmath>

namespace hilrig::host {
namespace {

// Quaternion kept as raw (x, y, z, w) coefficients inside RK4 so that intermediate stages can
// be scaled and added without Eigen's unit-quaternion semantics getting in the way.
using QuatCoeffs = Eigen::Vector4d;

// dq/dt = 1/2 q ⊗ (0, w) with w in the body frame.
inline QuatCoeffs QuatDerivative(const QuatCoeffs& q, const Eigen::Vector3d& w) {
  const Eigen::Vector3d v = q.head<3>();
  const double s = q.w();
  QuatCoeffs dq;
  dq.head<3>() = 0.5 * (s * w + v.cross(w));
  dq.w() = -0.5 * v.dot(w);
  return dq;
}

// Euler's equations: I dw/dt = tau - w x (I w).
inline Eigen::Vector3d AngularAcceleration(const Eigen::Vector3d& inertia,
                                           const Eigen::Vector3d& inv_inertia,
                                           const Eigen::Vector3d& torque,
                                           const Eigen::Vector3d& w) {
  return inv_inertia.cwiseProduct(torque - w.cross(inertia.cwiseProduct(w)));
}

// Exact rotation for a constant body rate over dt, used by the semi-implicit integrator.
inline Eigen::Quaterniond DeltaRotation(const Eigen::Vector3d& w, double dt) {
  const Eigen::Vector3d half_angle = 0.5 * dt * w;
  const double theta = half_angle.norm();
  if (theta < 1e-8) {
    // Second-order series; exact to double precision at this size, avoids 0/0.
    return Eigen::Quaterniond(1.0 - 0.5 * theta * theta, half_angle.x(), half_angle.y(),
                              half_angle.z());
  }
  const double k = std::sin(theta) / theta;
  return Eigen::Quaterniond(std::cos(theta), k * half_angle.x(), k * half_angle.y(),
                            k * half_angle.z());
}

}  // namespace

RigidBodyState StepRigidBody(const RigidBodyParams& params, const RigidBodyState& state,
                             const Wrench& wrench, double gravity_m_s2, double dt_s,
                             Integrator integrator) {
  const Eigen::Vector3d& inertia = params.inertia_kg_m2;
  const Eigen::Vector3d inv_inertia = inertia.cwiseInverse();
  const Eigen::Vector3d accel =
      wrench.force_world_n / params.mass_kg + Eigen::Vector3d(0.0, 0.0, -gravity_m_s2);
  const Eigen::Vector3d& tau = wrench.torque_body_nm;

  RigidBodyState next;
  if (integrator == Integrator::kSemiImplicitEuler) {
    next.velocity_m_s = state.velocity_m_s + accel * dt_s;
    next.position_m = state.position_m + next.velocity_m_s * dt_s;
    next.angular_velocity_rad_s =
        state.angular_velocity_rad_s +
        AngularAcceleration(inertia, inv_inertia, tau, state.angular_velocity_rad_s) * dt_s;
    next.orientation = state.orientation * DeltaRotation(next.angular_velocity_rad_s, dt_s);
  } else {
    // Constant acceleration: RK4 reproduces the closed form exactly, so skip the stages.
    next.position_m = state.position_m + state.velocity_m_s * dt_s + 0.5 * accel * dt_s * dt_s;
    next.velocity_m_s = state.velocity_m_s + accel * dt_s;

    const double h = dt_s;
    const QuatCoeffs q0 = state.orientation.coeffs();
    const Eigen::Vector3d& w0 = state.angular_velocity_rad_s;

    const QuatCoeffs kq1 = QuatDerivative(q0, w0);
    const Eigen::Vector3d kw1 = AngularAcceleration(inertia, inv_inertia, tau, w0);

    const QuatCoeffs q2 = q0 + 0.5 * h * kq1;
    const Eigen::Vector3d w2 = w0 + 0.5 * h * kw1;
    const QuatCoeffs kq2 = QuatDerivative(q2, w2);
    const Eigen::Vector3d kw2 = AngularAcceleration(inertia, inv_inertia, tau, w2);

    const QuatCoeffs q3 = q0 + 0.5 * h * kq2;
    const Eigen::Vector3d w3 = w0 + 0.5 * h * kw2;
    const QuatCoeffs kq3 = QuatDerivative(q3, w3);
    const Eigen::Vector3d kw3 = AngularAcceleration(inertia, inv_inertia, tau, w3);

    const QuatCoeffs q4 = q0 + h * kq3;
    const Eigen::Vector3d w4 = w0 + h * kw3;
    const QuatCoeffs kq4 = QuatDerivative(q4, w4);
    const Eigen::Vector3d kw4 = AngularAcceleration(inertia, inv_inertia, tau, w4);

    next.orientation.coeffs() = q0 + (h / 6.0) * (kq1 + 2.0 * kq2 + 2.0 * kq3 + kq4);
    next.angular_velocity_rad_s = w0 + (h / 6.0) * (kw1 + 2.0 * kw2 + 2.0 * kw3 + kw4);
  }
  // Keeps R_WB a rotation; the drift per step is O(h^5) but accumulates over hours otherwise.
  next.orientation.normalize();
  return next;
}

double MechanicalEnergy(const RigidBodyParams& params, const RigidBodyState& state,
                        double gravity_m_s2) {
  const Eigen::Vector3d& w = state.angular_velocity_rad_s;
  const double translational = 0.5 * params.mass_kg * state.velocity_m_s.squaredNorm();
  const double rotational = 0.5 * w.dot(params.inertia_kg_m2.cwiseProduct(w));
  const double potential = params.mass_kg * gravity_m_s2 * state.position_m.z();
  return translational + rotational + potential;
}

Eigen::Vector3d AngularMomentumWorld(const RigidBodyParams& params, const RigidBodyState& state) {
  return state.orientation * params.inertia_kg_m2.cwiseProduct(state.angular_velocity_rad_s);
}

}  // namespace hilrig::host
