// Inner loops of the flight controller: an attitude P loop that commands a body rate, cascaded
// with a body-rate PID that commands a body torque.
//
//   R_e = 2 sgn(w) vec(q⁻¹ ⊗ q_d)   (body-frame rotation from the current to the desired attitude)
//   ω_d = clamp(K_R R_e, ±max_rate),   ω_e = ω_d − ω
//   τ   = K_P ω_e + K_I ∫ω_e + K_D ω̇_e + ω × J ω
//
// R_e is the quaternion form of the SO(3) error: it equals the rotation vector for small errors,
// is 2 sin(angle/2) along the error axis in general (so the loop keeps pushing up to 180 degrees,
// unlike the matrix form vee(R_dᵀR − RᵀR_d)/2 that fades out past 90 degrees), always takes the
// short way round and costs no trig. With R_e pointing from current to desired a positive K_R
// drives the error to zero.
//
// ω̇_e is a finite difference through a first-order low-pass (cut-off `derivative_cutoff_hz`)
// because the raw difference of a 1 kHz gyro is mostly noise. The integral is clamped per axis so
// a long saturation (e.g. on the ground) cannot wind it up. The gyroscopic term is feed-forward and
// vanishes when `inertia_kg_m2` is left at zero.
#pragma once

#include <cmath>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct AttitudeGains {
  Vec3<S> k_r_per_s;  // attitude error (rad) -> desired rate (rad/s)
  Vec3<S> k_p_nm_s;   // rate error (rad/s) -> torque
  Vec3<S> k_i_nm;     // integrated rate error (rad) -> torque
  Vec3<S> k_d_nm_s2;  // rate error derivative (rad/s²) -> torque
  Vec3<S> max_rate_rad_s;
  Vec3<S> integral_limit_rad;
  S derivative_cutoff_hz;
  Vec3<S> inertia_kg_m2 = Vec3<S>::Zero();  // diagonal body inertia for ω × Jω; zero disables it
};

template <typename S>
struct AttitudeState {
  Vec3<S> rate_error_integral = Vec3<S>::Zero();
  Vec3<S> previous_rate_error = Vec3<S>::Zero();
  Vec3<S> filtered_rate_error_derivative = Vec3<S>::Zero();
  bool has_previous = false;
};

// Attitude error R_e (see header), body frame, rad-like.
template <typename S>
Vec3<S> AttitudeError(const Quat<S>& attitude_desired, const Quat<S>& attitude) {
  return QuatErrorVector<S>(attitude.conjugate() * attitude_desired);
}

// Returns the body torque (N·m). A non-positive or non-finite dt leaves the integrator and the
// derivative filter untouched (there is no time step to integrate or differentiate over) but still
// returns the torque for the current error.
template <typename S>
Vec3<S> StepAttitude(const AttitudeGains<S>& gains, AttitudeState<S>& state,
                     const NoDeduce<Quat<S>>& attitude_desired, const NoDeduce<Quat<S>>& attitude,
                     const NoDeduce<Vec3<S>>& angular_velocity_body_rad_s, NoDeduce<S> dt_s) {
  const Vec3<S> rate_desired_rad_s =
      ClampSymmetric<S>(gains.k_r_per_s.cwiseProduct(AttitudeError<S>(attitude_desired, attitude)),
                        gains.max_rate_rad_s);
  const Vec3<S> rate_error_rad_s = rate_desired_rad_s - angular_velocity_body_rad_s;

  if (dt_s > S(0) && std::isfinite(dt_s) && AllFinite(rate_error_rad_s)) {
    state.rate_error_integral = ClampSymmetric<S>(
        state.rate_error_integral + rate_error_rad_s * dt_s, gains.integral_limit_rad);
    if (state.has_previous) {
      const Vec3<S> raw_derivative = (rate_error_rad_s - state.previous_rate_error) / dt_s;
      // Exact discretisation weight of a first-order low-pass would need exp(); dt/(dt + tau) is
      // its backward-Euler equivalent and stays in [0, 1) for any dt (written with ω_c = 1/tau).
      const S wc_dt = S(2 * EIGEN_PI) * gains.derivative_cutoff_hz * dt_s;
      const S alpha = wc_dt / (wc_dt + S(1));
      state.filtered_rate_error_derivative +=
          alpha * (raw_derivative - state.filtered_rate_error_derivative);
    }
    state.previous_rate_error = rate_error_rad_s;
    state.has_previous = true;
  }

  const Vec3<S>& w = angular_velocity_body_rad_s;
  return gains.k_p_nm_s.cwiseProduct(rate_error_rad_s) +
         gains.k_i_nm.cwiseProduct(state.rate_error_integral) +
         gains.k_d_nm_s2.cwiseProduct(state.filtered_rate_error_derivative) +
         w.cross(gains.inertia_kg_m2.cwiseProduct(w));
}

}  // namespace hilrig::dut_fw
