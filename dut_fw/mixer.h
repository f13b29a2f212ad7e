// Control allocation: turns a collective thrust and a body torque into four rotor thrusts for the
// X layout shared with the host plant (a = L/√2):
//
//   rotor 0 (+a, −a) front-right, yaw sign −1      rotor 2 (+a, +a) front-left, yaw sign +1
//   rotor 1 (−a, +a) back-left,   yaw sign −1      rotor 3 (−a, −a) back-right, yaw sign +1
//
//   T = Σ T_i,   τx = Σ y_i T_i,   τy = −Σ x_i T_i,   τz = Σ s_i κ T_i
//
// with κ = torque_per_thrust_m and s_i the yaw sign.
//
// The rows of that allocation matrix are mutually orthogonal, so its inverse is its transpose with
// each row scaled by 1/|row|²: no matrix inverse at run time.
//
// Saturation strategy (priority roll/pitch > collective > yaw). Rotors are limited to [0, max]:
//  1. The roll/pitch part alone is scaled down (direction kept) if its spread exceeds [0, max];
//     attitude is what keeps the vehicle in the air, so it is never traded for anything else.
//  2. The collective is shifted by the least amount that fits the roll/pitch part in the range.
//  3. The yaw part is scaled by the largest factor in [0, 1] that keeps every rotor in range; yaw
//     is the weakest and least urgent axis, and it alone would otherwise eat the roll/pitch margin.
// A non-finite input returns all rotors at zero: nothing non-finite may ever reach an ESC, and
// stopped motors are the one well-defined answer (upstream guards keep this path unused).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct MixerGeometry {
  S arm_length_m;            // rotor centre to vehicle centre
  S torque_per_thrust_m;     // κ: yaw reaction torque per unit thrust
  S max_thrust_per_rotor_n;  // upper limit of each rotor; the lower is 0
};

inline constexpr std::array<int, 4> kRotorYawSign = {-1, -1, +1, +1};

// Rotor i position (x, y) in the body frame, m.
template <typename S>
Eigen::Matrix<S, 2, 1> RotorPositionBody(const MixerGeometry<S>& geometry, int rotor) {
  const S a = geometry.arm_length_m / std::sqrt(S(2));
  static constexpr std::array<int, 4> kX = {+1, -1, +1, -1};
  static constexpr std::array<int, 4> kY = {-1, +1, +1, -1};
  return Eigen::Matrix<S, 2, 1>(S(kX[rotor]) * a, S(kY[rotor]) * a);
}

// Maps rotor thrusts (T_0..T_3) to (collective N, τx, τy, τz N·m).
template <typename S>
Eigen::Matrix<S, 4, 4> AllocationMatrix(const MixerGeometry<S>& geometry) {
  Eigen::Matrix<S, 4, 4> a;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Matrix<S, 2, 1> r = RotorPositionBody(geometry, i);
    a(0, i) = S(1);
    a(1, i) = r.y();
    a(2, i) = -r.x();
    a(3, i) = S(kRotorYawSign[i]) * geometry.torque_per_thrust_m;
  }
  return a;
}

// The geometry's derived constants of the allocation, computed once per geometry instead of once
// per control step. The expressions (and their order) are those Mix used inline, so the thrusts
// are bit-identical; the yaw share keeps its division (a reciprocal would round differently).
template <typename S>
struct MixerConstants {
  S inv_4a;                  // 1 / (4a), a = L/√2: roll/pitch row norm² is 4a²
  S four_kappa_m;            // 4κ: yaw row norm² over κ
  S max_thrust_per_rotor_n;  // copied so the control step reads one struct
};

template <typename S>
MixerConstants<S> MixerConstantsOf(const MixerGeometry<S>& geometry) {
  const S a = geometry.arm_length_m / std::sqrt(S(2));
  return MixerConstants<S>{S(1) / (S(4) * a), S(4) * geometry.torque_per_thrust_m,
                           geometry.max_thrust_per_rotor_n};
}

// Mix below with the constants given and the thrusts written into `thrust_n`.
template <typename S>
void MixInto(const MixerConstants<S>& constants, NoDeduce<S> collective_thrust_n,
             const NoDeduce<Vec3<S>>& torque_body_nm, std::array<S, 4>& thrust_n) {
  if (!std::isfinite(collective_thrust_n) || !AllFinite(torque_body_nm)) {
    thrust_n = {S(0), S(0), S(0), S(0)};
    return;
  }

  const S max_n = constants.max_thrust_per_rotor_n;
  // Per-rotor shares from the scaled transpose: roll/pitch row norm² is 4a², yaw row norm² is 4κ².
  const S roll_share = torque_body_nm.x() * constants.inv_4a;
  const S pitch_share = torque_body_nm.y() * constants.inv_4a;
  const S yaw_share = torque_body_nm.z() / constants.four_kappa_m;
  // y_i/a and -x_i/a for rotors 0..3 (see layout above).
  std::array<S, 4> rp = {-roll_share - pitch_share, roll_share + pitch_share,
                         roll_share - pitch_share, -roll_share + pitch_share};

  // 1. Roll/pitch spread.
  S rp_min = rp[0];
  S rp_max = rp[0];
  for (int i = 1; i < 4; ++i) {
    rp_min = std::min(rp_min, rp[i]);
    rp_max = std::max(rp_max, rp[i]);
  }
  const S spread = rp_max - rp_min;
  if (spread > max_n) {
    const S scale = max_n / spread;
    for (S& v : rp) v *= scale;
    rp_min *= scale;
    rp_max *= scale;
  }
  // 2. Collective, shifted minimally so that the roll/pitch part fits.
  // (max/min rather than std::clamp: rounding can leave the bounds crossed by an ulp.)
  const S base = std::min(std::max(collective_thrust_n / S(4), -rp_min), max_n - rp_max);
  // 3. Yaw, scaled to fit what remains. Every rotor gets ±yaw_share, so the scale is the smallest
  // headroom in the direction each rotor moves over |yaw_share| (one division, and only if short).
  S headroom = std::numeric_limits<S>::infinity();
  for (int i = 0; i < 4; ++i) {
    const S level = base + rp[i];
    const bool up = (kRotorYawSign[i] > 0) == (yaw_share > S(0));
    headroom = std::min(headroom, up ? max_n - level : level);
  }
  const S yaw_magnitude = std::abs(yaw_share);
  S yaw_applied = yaw_share;
  if (headroom < yaw_magnitude) {  // implies yaw_magnitude > 0 unless rounding left headroom < 0
    yaw_applied =
        yaw_magnitude > S(0) ? yaw_share * (std::max(headroom, S(0)) / yaw_magnitude) : S(0);
  }
  // The final clamp only removes rounding residue; the steps above already fit the range.
  for (int i = 0; i < 4; ++i) {
    thrust_n[i] = std::clamp(base + rp[i] + S(kRotorYawSign[i]) * yaw_applied, S(0), max_n);
  }
}

template <typename S>
std::array<S, 4> Mix(const MixerGeometry<S>& geometry, NoDeduce<S> collective_thrust_n,
                     const NoDeduce<Vec3<S>>& torque_body_nm) {
  std::array<S, 4> thrust_n;
  MixInto<S>(MixerConstantsOf(geometry), collective_thrust_n, torque_body_nm, thrust_n);
  return thrust_n;
}

}  // namespace hilrig::dut_fw
