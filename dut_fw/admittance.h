// Admittance (compliance) layer between the mission reference and the position controller. It
// turns the measured external force into a desired offset from the reference, so a grasped or
// pushed vehicle yields like a mass-spring-damper instead of fighting the contact:
//
//   M (p̈d − p̈r) + D (ṗd − ṗr) + K (pd − pr) = f_ext        (diagonal M, D, K, world frame)
//
// Integration is semi-implicit (symplectic) Euler: the rate is advanced first with the old offset
// and the offset then uses the new rate. Per axis, with c = D/M and k = K/M, the discrete map is
// stable iff  0 < c·dt < 2  and  k·dt² + 2·c·dt < 4,  i.e.  dt < (√(c² + 4k) − c) / k.
// MaxStableAdmittanceDt() evaluates that bound; keep the control period well below it (for the
// defaults of flight_controller.h the stiffest axis, z with M = 1 kg, D = 20 N·s/m, K = 100 N/m,
// bounds it at 0.083 s, and x, y with D = 12 N·s/m, K = 36 N/m at 0.138 s, both far above the 1 ms
// control step; only a very light virtual mass with heavy damping gets close).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct AdmittanceParams {
  Vec3<S> mass_kg;            // virtual mass per world axis, > 0
  Vec3<S> damping_n_s_per_m;  // >= 0
  Vec3<S> stiffness_n_per_m;  // >= 0; 0 makes the axis a pure damper (the offset drifts)
};

template <typename S>
struct AdmittanceState {
  Vec3<S> offset_m = Vec3<S>::Zero();         // pd − pr
  Vec3<S> offset_rate_m_s = Vec3<S>::Zero();  // ṗd − ṗr
  std::uint32_t rejected_inputs = 0;          // steps whose force or dt was not usable
};

template <typename S>
struct Reference {
  Vec3<S> position_m = Vec3<S>::Zero();
  Vec3<S> velocity_m_s = Vec3<S>::Zero();
  Vec3<S> acceleration_m_s2 = Vec3<S>::Zero();
  S yaw_rad = S(0);
};

template <typename S>
bool AllFinite(const Reference<S>& r) {
  return AllFinite(r.position_m) && AllFinite(r.velocity_m_s) && AllFinite(r.acceleration_m_s2) &&
         std::isfinite(r.yaw_rad);
}

// Largest dt (s) for which the semi-implicit Euler update is stable on every axis (see header).
template <typename S>
S MaxStableAdmittanceDt(const AdmittanceParams<S>& params) {
  S bound = std::numeric_limits<S>::infinity();
  for (int i = 0; i < 3; ++i) {
    const S c = params.damping_n_s_per_m[i] / params.mass_kg[i];
    const S k = params.stiffness_n_per_m[i] / params.mass_kg[i];
    S axis_bound;
    if (k > S(0)) {
      axis_bound = (std::sqrt(c * c + S(4) * k) - c) / k;
    } else {
      axis_bound = c > S(0) ? S(2) / c : std::numeric_limits<S>::infinity();
    }
    bound = std::min(bound, axis_bound);
  }
  return bound;
}

// Advances the offset by dt with f_ext (world, N) and writes the desired (pd, vd, ad) for this step
// into `desired` (which must not alias `reference`). A non-finite force is treated as zero force
// and a non-positive or non-finite dt holds the offset; both are counted in state.rejected_inputs,
// because a bad sample must never poison the offset that the position loop will chase. Returns
// whether the force was finite, so a caller feeding the same force onward need not check it again.
template <typename S>
bool StepAdmittanceInto(const AdmittanceParams<S>& params, AdmittanceState<S>& state,
                        const NoDeduce<Reference<S>>& reference,
                        const NoDeduce<Vec3<S>>& external_force_world_n, NoDeduce<S> dt_s,
                        Reference<S>& desired) {
  Vec3<S> force_n = external_force_world_n;
  const bool force_finite = AllFinite(force_n);
  if (!force_finite) {
    force_n.setZero();
    ++state.rejected_inputs;
  }
  const Vec3<S> accel_m_s2 =
      (force_n - params.damping_n_s_per_m.cwiseProduct(state.offset_rate_m_s) -
       params.stiffness_n_per_m.cwiseProduct(state.offset_m))
          .cwiseQuotient(params.mass_kg);
  if (dt_s > S(0) && std::isfinite(dt_s)) {
    state.offset_rate_m_s += accel_m_s2 * dt_s;
    state.offset_m += state.offset_rate_m_s * dt_s;
  } else {
    ++state.rejected_inputs;
  }

  desired.position_m = reference.position_m + state.offset_m;
  desired.velocity_m_s = reference.velocity_m_s + state.offset_rate_m_s;
  desired.acceleration_m_s2 = reference.acceleration_m_s2 + accel_m_s2;
  desired.yaw_rad = reference.yaw_rad;
  return force_finite;
}

// StepAdmittanceInto, returning the desired reference.
template <typename S>
Reference<S> StepAdmittance(const AdmittanceParams<S>& params, AdmittanceState<S>& state,
                            const NoDeduce<Reference<S>>& reference,
                            const NoDeduce<Vec3<S>>& external_force_world_n, NoDeduce<S> dt_s) {
  Reference<S> desired;
  StepAdmittanceInto<S>(params, state, reference, external_force_world_n, dt_s, desired);
  return desired;
}

}  // namespace hilrig::dut_fw
