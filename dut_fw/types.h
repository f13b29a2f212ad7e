// Shared vocabulary of the controller firmware: fixed-size Eigen aliases and the few SO(3) and
// quaternion helpers the estimator and controllers need. Everything here is allocation-free and
// templated on the scalar so the same code runs in float on the target and in double on the host.
//
// Frames (shared with the host plant): world z up, body x forward / y left / z up; a quaternion
// `q` rotates body vectors into the world (R_WB).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <type_traits>

namespace hilrig::dut_fw {

// Marks a parameter as a non-deduced context, so the scalar of a step function is deduced from its
// params/state structs alone and callers may pass Eigen expressions (`Vec3<S>::Zero()`) or plain
// literals (`1e-3` for a float controller) for the other arguments.
template <typename T>
using NoDeduce = std::type_identity_t<T>;

template <typename S>
using Vec3 = Eigen::Matrix<S, 3, 1>;
template <typename S>
using Quat = Eigen::Quaternion<S>;
template <typename S>
using Mat3 = Eigen::Matrix<S, 3, 3>;

// Skew-symmetric matrix such that Hat(a) * b == a.cross(b).
template <typename S>
Mat3<S> Hat(const Vec3<S>& v) {
  Mat3<S> m;
  m << S(0), -v.z(), v.y(), v.z(), S(0), -v.x(), -v.y(), v.x(), S(0);
  return m;
}

// Inverse of Hat; takes the antisymmetric part so that a slightly non-skew input still maps to the
// closest rotation-vector-like quantity.
template <typename S>
Vec3<S> Vee(const Mat3<S>& m) {
  return Vec3<S>(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1)) * S(0.5);
}

// Quaternion of the rotation by the rotation vector `v` (axis * angle, rad). Up to 0.063 rad (a
// 63 rad/s body rate over a 1 ms IMU step, i.e. every step the estimator takes in flight) the
// half-angle cosine and sine/angle ratio come from their Taylor series, truncated where the
// remainder falls below double rounding; that replaces two libm trig calls and a sqrt on the hot
// path and also avoids 0/0 at zero rotation.
//
// Forced inline (as is Rotate): both sit on the 1 kHz path with two or three callers each, and
// out of line the argument and result traffic through memory costs as much as their arithmetic.
template <typename S>
EIGEN_ALWAYS_INLINE Quat<S> QuatExp(const Vec3<S>& v) {
  const S angle_sq = v.squaredNorm();
  const S x2 = angle_sq * S(0.25);  // (angle / 2)²
  S w;
  S k;  // sin(angle / 2) / angle
  if (x2 < S(1e-3)) {
    w = S(1) - x2 * (S(1) / S(2) - x2 * (S(1) / S(24) - x2 * (S(1) / S(720))));
    k = S(0.5) * (S(1) - x2 * (S(1) / S(6) - x2 * (S(1) / S(120) - x2 * (S(1) / S(5040)))));
  } else {
    const S angle = std::sqrt(angle_sq);
    w = std::cos(angle * S(0.5));
    k = std::sin(angle * S(0.5)) / angle;
  }
  return Quat<S>(w, k * v.x(), k * v.y(), k * v.z());
}

// Small-angle inverse of QuatExp: 2 * vec(q) on the short arc. Exact to first order, equal to
// 2 sin(angle / 2) * axis in general, which is monotonic up to 180 degrees and needs no trig; that
// is all the feedback laws need (they only require the sign and a bounded magnitude).
template <typename S>
Vec3<S> QuatErrorVector(const Quat<S>& q) {
  const S sign = q.w() < S(0) ? S(-1) : S(1);
  return S(2) * sign * q.vec();
}

// R(q) v for a unit quaternion, written out (v + w t + u × t with t = 2 u × v) because Eigen's
// generic quaternion-vector product spends more on SIMD shuffles than on arithmetic for 3-vectors.
template <typename S>
EIGEN_ALWAYS_INLINE Vec3<S> Rotate(const Quat<S>& q, const Vec3<S>& v) {
  const S w = q.w(), ux = q.x(), uy = q.y(), uz = q.z();
  const S tx = S(2) * (uy * v.z() - uz * v.y());
  const S ty = S(2) * (uz * v.x() - ux * v.z());
  const S tz = S(2) * (ux * v.y() - uy * v.x());
  return Vec3<S>(v.x() + w * tx + (uy * tz - uz * ty), v.y() + w * ty + (uz * tx - ux * tz),
                 v.z() + w * tz + (ux * ty - uy * tx));
}

// R(q) e_z: the body z axis (thrust direction) in the world, for a unit quaternion.
template <typename S>
Vec3<S> BodyZInWorld(const Quat<S>& q) {
  return Vec3<S>(S(2) * (q.x() * q.z() + q.w() * q.y()), S(2) * (q.y() * q.z() - q.w() * q.x()),
                 S(1) - S(2) * (q.x() * q.x() + q.y() * q.y()));
}

// Brings a quaternion that is within rounding of unit norm back to it with one Newton step on
// 1/|q| (no sqrt, no division); use after every incremental update of an attitude, where the norm
// error never has time to grow. Far-from-unit quaternions need normalized() instead.
template <typename S>
Quat<S> Renormalized(const Quat<S>& q) {
  return Quat<S>(q.coeffs() * ((S(3) - q.squaredNorm()) * S(0.5)));
}

// ZYX-Euler yaw (heading of the body x axis projected on the horizontal plane) of a body->world
// rotation.
template <typename S>
S YawRad(const Quat<S>& q) {
  return std::atan2(S(2) * (q.w() * q.z() + q.x() * q.y()),
                    S(1) - S(2) * (q.y() * q.y() + q.z() * q.z()));
}

template <typename S>
bool AllFinite(const Vec3<S>& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

template <typename S>
bool AllFinite(const Quat<S>& q) {
  return std::isfinite(q.w()) && std::isfinite(q.x()) && std::isfinite(q.y()) &&
         std::isfinite(q.z());
}

// Element-wise clamp to [-limit, +limit] (limit >= 0 per axis).
template <typename S>
Vec3<S> ClampSymmetric(const Vec3<S>& v, const Vec3<S>& limit) {
  return v.cwiseMax(-limit).cwiseMin(limit);
}

}  // namespace hilrig::dut_fw
