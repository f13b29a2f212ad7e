// Outer (translational) loop of the flight controller: a cascaded PD on the position error that
// produces the thrust vector the vehicle must point along, then splits it into a desired attitude
// (for the attitude loop) and a collective thrust (for the mixer).
//
//   a_cmd = p̈d + Kv (ṗd − ṗ) + Kp (pd − p),   F = m (a_cmd + g e_z) − f_ext        (world frame)
//
// f_ext is the contacts' measured force on the vehicle (the tactile sum rotated into the world).
// m is the vehicle alone, so without the −f_ext term a held object's weight would be fought only by
// the PD and sag the vehicle by m_obj g / (m Kp) (≈ 0.35 m for a 180 g bottle at Kp = 9 s⁻²). The
// tactile pads measure that load directly, so the thrust carries it as a feed-forward (a held
// weight makes f_ext.z < 0 and the thrust grows); the admittance upstream still sees the same
// force, so its deliberate give f/K becomes the only static position error under a payload. A
// non-finite force is ignored (zero feed-forward): a broken tactile sample must never reach the
// rotors.
//
// Limits, applied after the feed-forward, in this order and for these reasons:
//  1. F_z is floored at max(min collective, 1e-3 m g) and capped at the max collective: rotors
//     cannot pull down, and a positive floor keeps the thrust direction (hence the desired
//     attitude) defined in a free-fall command.
//  2. The horizontal part is scaled so that the tilt of F from vertical is <= max_tilt_rad.
//  3. If |F| exceeds the maximum collective thrust, the vertical part is kept and the horizontal
//     part is shortened further (altitude has priority over horizontal tracking: losing altitude
//     near an object or the ground is the worse failure).
// The desired attitude has its body z along F and its ZYX yaw equal to the reference yaw. The
// collective thrust is F projected on the *current* body z axis, so the vehicle does not push
// sideways with full thrust while it is still rotating toward the desired attitude.
#pragma once

#include <algorithm>
#include <cmath>

#include "dut_fw/admittance.h"
#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct PositionGains {
  Vec3<S> kp_per_s2;
  Vec3<S> kv_per_s;
  S mass_kg;
  S gravity_m_s2 = S(9.81);
  S max_tilt_rad;  // clamped internally to [0, 85 deg] so the tilt tangent stays finite
  S min_collective_thrust_n;
  S max_collective_thrust_n;
};

template <typename S>
struct PositionCommand {
  S collective_thrust_n = S(0);
  Quat<S> attitude_desired = Quat<S>::Identity();
  Vec3<S> thrust_world_n = Vec3<S>::Zero();  // the limited thrust vector F
};

// cos and sin of half a yaw angle, the only trig AttitudeFromThrustAndYaw needs. The reference
// yaw is constant over most of a flight while the position loop runs at 1 kHz, so a controller
// keeps the last pair in its state (YawTrigFor) and calls libm only when the yaw changes.
template <typename S>
struct HalfYawTrig {
  S yaw_rad = S(0);
  S cos_half = S(1);  // cos(yaw_rad / 2)
  S sin_half = S(0);  // sin(yaw_rad / 2)
};

template <typename S>
HalfYawTrig<S> HalfYawTrigOf(S yaw_rad) {
  const S half_yaw = S(0.5) * yaw_rad;
  return HalfYawTrig<S>{yaw_rad, std::cos(half_yaw), std::sin(half_yaw)};
}

// `cache` brought to `yaw_rad`: reused when it already holds the same value (sign of zero
// included, since sin(−0) is −0), recomputed otherwise, so the result is bit-identical to
// HalfYawTrigOf(yaw_rad). A NaN never compares equal and is recomputed every time.
template <typename S>
const HalfYawTrig<S>& YawTrigFor(HalfYawTrig<S>& cache, NoDeduce<S> yaw_rad) {
  if (!(yaw_rad == cache.yaw_rad && std::signbit(yaw_rad) == std::signbit(cache.yaw_rad))) {
    cache = HalfYawTrigOf<S>(yaw_rad);
  }
  return cache;
}

// Rotation body->world whose body z is along `thrust` (any vector with a positive z part) and whose
// ZYX-Euler yaw is `yaw.yaw_rad`, built as R = Rz(yaw) Ry(pitch) Rx(roll) directly in quaternion
// form: with F' = Rz(−yaw) F, roll and pitch follow from F' = |F| (sin p cos r, −sin r, cos p cos
// r), and each half-angle quaternion is the normalised (1 + cos, sin) pair, so the only trig is the
// yaw half-angle, given. (A rotation-matrix-to-quaternion conversion costs several times more.)
template <typename S>
Quat<S> AttitudeFromThrustAndYaw(const Vec3<S>& thrust, const HalfYawTrig<S>& yaw) {
  const S cz = yaw.cos_half;
  const S sz = yaw.sin_half;
  const S cos_yaw = cz * cz - sz * sz;
  const S sin_yaw = S(2) * cz * sz;
  const S fx = cos_yaw * thrust.x() + sin_yaw * thrust.y();  // F in the yawed frame
  const S fy = -sin_yaw * thrust.x() + cos_yaw * thrust.y();
  const S fz = thrust.z();
  const S f_xz = std::sqrt(fx * fx + fz * fz);  // |F| cos(roll)
  const S f = std::sqrt(fx * fx + fy * fy + fz * fz);
  // Unnormalised half-angle pairs: (1 + cos r, sin r) ∝ (|F| + |F| cos r, −F'_y) and
  // (1 + cos p, sin p) ∝ (|F| cos r + F'_z, F'_x). Their squared norms are 2|F|(|F| + |F| cos r)
  // and 2|F| cos r (|F| cos r + F'_z), so one sqrt normalises the product of both.
  const S rc = f + f_xz, rs = -fy;
  const S pc = f_xz + fz, ps = fx;
  const S scale = S(1) / std::sqrt(S(4) * f * rc * f_xz * pc);
  // Ry(p) Rx(r) as the quaternion product of (cp, 0, sp, 0) and (cr, sr, 0, 0).
  const S w = scale * pc * rc, x = scale * pc * rs, y = scale * ps * rc, z = -scale * ps * rs;
  // Rz(yaw) = (cz, 0, 0, sz) on the left.
  return Quat<S>(cz * w - sz * z, cz * x - sz * y, cz * y + sz * x, cz * z + sz * w);
}

template <typename S>
Quat<S> AttitudeFromThrustAndYaw(const Vec3<S>& thrust, NoDeduce<S> yaw_rad) {
  return AttitudeFromThrustAndYaw<S>(thrust, HalfYawTrigOf<S>(yaw_rad));
}

// tan of max_tilt_rad clamped to [0, 85 deg]: a constant of the gains, so a controller that steps
// them repeatedly computes it once (FlightController does) instead of once per control step.
template <typename S>
S MaxTiltTangent(const PositionGains<S>& gains) {
  return std::tan(std::clamp(gains.max_tilt_rad, S(0), S(85.0 * EIGEN_PI / 180.0)));
}

// ComputePositionCommand below, with `max_tilt_tangent` = MaxTiltTangent(gains) given and the yaw's
// half-angle trig taken from `yaw_trig` (the previous step's, updated here when the yaw changed).
// Precondition: `external_force_world_n` is finite (ComputePositionCommand zeroes a non-finite one
// before calling this; FlightController has it from the admittance's check of the same force).
template <typename S>
PositionCommand<S> ComputePositionCommandWithTiltTangent(
    const PositionGains<S>& gains, NoDeduce<S> max_tilt_tangent, HalfYawTrig<S>& yaw_trig,
    const NoDeduce<Reference<S>>& desired, const NoDeduce<Vec3<S>>& position_m,
    const NoDeduce<Vec3<S>>& velocity_m_s, const NoDeduce<Quat<S>>& attitude,
    const NoDeduce<Vec3<S>>& external_force_world_n) {
  const S weight_n = gains.mass_kg * gains.gravity_m_s2;
  const Vec3<S>& feedforward_n = external_force_world_n;
  const Vec3<S> accel_cmd_m_s2 = desired.acceleration_m_s2 +
                                 gains.kv_per_s.cwiseProduct(desired.velocity_m_s - velocity_m_s) +
                                 gains.kp_per_s2.cwiseProduct(desired.position_m - position_m);
  Vec3<S> thrust_n = gains.mass_kg * accel_cmd_m_s2;
  thrust_n.z() += weight_n;
  thrust_n -= feedforward_n;
  // A non-finite input would otherwise reach the motors; hovering level (still carrying the
  // measured load, if that is finite) is the least bad answer.
  if (!AllFinite(thrust_n)) {
    const S load_hover_n = weight_n - feedforward_n.z();
    thrust_n = Vec3<S>(S(0), S(0), std::isfinite(load_hover_n) ? load_hover_n : weight_n);
  }

  const S max_thrust_n = gains.max_collective_thrust_n;
  S fz = std::max(thrust_n.z(), std::max(gains.min_collective_thrust_n, S(1e-3) * weight_n));
  fz = std::min(fz, max_thrust_n);
  S horizontal_limit = fz * max_tilt_tangent;
  horizontal_limit =
      std::min(horizontal_limit, std::sqrt(std::max(max_thrust_n * max_thrust_n - fz * fz, S(0))));
  Eigen::Matrix<S, 2, 1> horizontal = thrust_n.template head<2>();
  const S horizontal_n = horizontal.norm();
  if (horizontal_n > horizontal_limit) horizontal *= horizontal_limit / horizontal_n;

  PositionCommand<S> command;
  command.thrust_world_n = Vec3<S>(horizontal.x(), horizontal.y(), fz);
  // A non-finite yaw keeps the current heading rather than spinning to an arbitrary one.
  const S yaw_rad = std::isfinite(desired.yaw_rad) ? desired.yaw_rad : YawRad<S>(attitude);
  command.attitude_desired =
      AttitudeFromThrustAndYaw<S>(command.thrust_world_n, YawTrigFor<S>(yaw_trig, yaw_rad));
  const Vec3<S> body_z_world = BodyZInWorld<S>(attitude);
  S collective_n = command.thrust_world_n.dot(body_z_world);
  if (!std::isfinite(collective_n)) collective_n = fz;
  command.collective_thrust_n =
      std::clamp(collective_n, gains.min_collective_thrust_n, max_thrust_n);
  return command;
}

template <typename S>
PositionCommand<S> ComputePositionCommand(
    const PositionGains<S>& gains, const NoDeduce<Reference<S>>& desired,
    const NoDeduce<Vec3<S>>& position_m, const NoDeduce<Vec3<S>>& velocity_m_s,
    const NoDeduce<Quat<S>>& attitude,
    const NoDeduce<Vec3<S>>& external_force_world_n = Vec3<S>::Zero()) {
  HalfYawTrig<S> yaw_trig;
  // A non-finite force is ignored (see header), here where it enters.
  const Vec3<S> feedforward_n =
      AllFinite(external_force_world_n) ? external_force_world_n : Vec3<S>::Zero();
  return ComputePositionCommandWithTiltTangent<S>(gains, MaxTiltTangent(gains), yaw_trig, desired,
                                                  position_m, velocity_m_s, attitude,
                                                  feedforward_n);
}

}  // namespace hilrig::dut_fw
