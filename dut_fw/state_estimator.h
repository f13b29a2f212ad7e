// State estimator of the flight controller: a complementary filter that dead-reckons with the IMU
// (gyro, accelerometer; body frame, ~1 kHz) and corrects with delayed VIO poses (position and
// orientation, ~30 Hz, 20-60 ms late, stamped with their capture time).
//
// Latency. Every IMU step stores (time, position, velocity, orientation) in a fixed-size ring. A
// VIO pose is compared with the estimate *at its capture time* (interpolated from the ring), and
// the resulting correction is applied both to the current state and to every stored entry, so the
// history stays consistent with the corrected trajectory and the next pose does not see (and
// re-apply) the same innovation. Velocity corrections also move later positions by Δv·(t − t_c),
// which is what re-propagating from the capture time would have done. Poses older than the ring are
// rejected; the default 256 entries cover 256 ms at 1 kHz, several times the worst VIO latency.
//
// Corrections, per VIO update with innovation δp = p_vio − p̂(t_c), δθ = rotation from q̂(t_c) to
// q_vio in body axes, and T the time between VIO captures:
//   p += α δp,   v += β δp / T,   b_a −= γ R̂ᵀ δp / T²          (α-β-γ observer on position)
//   q ← exp(k_q R̂ δθ) ⊗ q,   b_g −= k_b δθ / T                  (Mahony-style on attitude)
// With the prediction over T in between, the per-update error dynamics have characteristic
// polynomials u³ + (α+β+γ/2)u² + (β+3γ/2)u + γ and u² + (k_q+k_b)u + k_b (u = z − 1). The defaults
// place all poles at z = 0.9: a 0.33 s time constant at 30 Hz, fast enough to catch a bias within
// a few seconds and slow enough to average VIO noise over ~10 frames. T is measured but clamped to
// [0.5, 2] × nominal_vio_period_s so a dropped or out-of-order frame cannot blow up the gains.
//
// Robustness: non-finite samples, a VIO quaternion that is far from unit norm, IMU timestamps that
// do not advance and stale VIO poses are rejected and counted; bias estimates are clamped.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
struct EstimatorGains {
  S position_gain;    // α, fraction of the position innovation applied per update
  S velocity_gain;    // β, Δv = β δp / T
  S accel_bias_gain;  // γ, Δb_a = −γ R̂ᵀ δp / T²
  S attitude_gain;    // k_q, fraction of the attitude innovation applied per update
  S gyro_bias_gain;   // k_b, Δb_g = −k_b δθ / T
  S gravity_m_s2 = S(9.81);
  S nominal_vio_period_s = S(1.0 / 30.0);
  S max_gyro_bias_rad_s = S(0.3);
  S max_accel_bias_m_s2 = S(2.0);
};

// All poles of both correction loops at z = `pole` per VIO update (see header).
template <typename S>
EstimatorGains<S> EstimatorGainsWithPoles(S pole) {
  const S d = S(1) - pole;
  EstimatorGains<S> gains;
  gains.accel_bias_gain = d * d * d;
  gains.velocity_gain = S(3) * d * d - S(1.5) * d * d * d;
  gains.position_gain = S(1) - pole * pole * pole;
  gains.gyro_bias_gain = d * d;
  gains.attitude_gain = S(2) * d - d * d;
  return gains;
}

template <typename S>
struct EstimatorHistoryEntry {
  std::int64_t time_ns = 0;
  Vec3<S> position_m;
  Vec3<S> velocity_m_s;
  Quat<S> orientation;
};

template <typename S, int kHistory = 256>
struct EstimatorState {
  static_assert(kHistory >= 2, "the history must hold at least two entries to interpolate");

  bool initialized = false;
  std::int64_t time_ns = 0;  // time of the latest accepted IMU sample (or of the first VIO pose)
  Vec3<S> position_m = Vec3<S>::Zero();
  Vec3<S> velocity_m_s = Vec3<S>::Zero();
  Vec3<S> gyro_bias_rad_s = Vec3<S>::Zero();
  Vec3<S> accel_bias_m_s2 = Vec3<S>::Zero();
  Quat<S> orientation = Quat<S>::Identity();         // R_WB
  Vec3<S> angular_velocity_rad_s = Vec3<S>::Zero();  // bias-corrected gyro, body frame

  bool has_time = false;                      // time_ns is meaningful
  std::int64_t last_vio_capture_time_ns = 0;  // valid once initialized

  // Ring of past estimates, oldest at (history_next - history_count) mod kHistory.
  std::array<EstimatorHistoryEntry<S>, kHistory> history{};
  int history_next = 0;
  int history_count = 0;

  std::uint32_t rejected_samples = 0;  // sum of the three counters below
  std::uint32_t rejected_non_finite = 0;
  std::uint32_t rejected_out_of_order = 0;  // IMU dt <= 0
  std::uint32_t rejected_stale_vio = 0;     // VIO capture time older than the history
};

namespace estimator_internal {

template <typename S, int N>
void Reject(EstimatorState<S, N>& state, std::uint32_t& counter) {
  ++counter;
  ++state.rejected_samples;
}

template <typename S, int N>
void PushHistory(EstimatorState<S, N>& state) {
  EstimatorHistoryEntry<S>& entry = state.history[state.history_next];
  entry.time_ns = state.time_ns;
  entry.position_m = state.position_m;
  entry.velocity_m_s = state.velocity_m_s;
  entry.orientation = state.orientation;
  state.history_next = (state.history_next + 1) % N;
  state.history_count = std::min(state.history_count + 1, N);
}

// k-th oldest entry, 0 <= k < history_count.
template <typename S, int N>
EstimatorHistoryEntry<S>& HistoryAt(EstimatorState<S, N>& state, int k) {
  return state.history[(state.history_next - state.history_count + k + N) % N];
}

}  // namespace estimator_internal

template <typename S, int N>
void PropagateImu(const EstimatorGains<S>& gains, EstimatorState<S, N>& state,
                  const NoDeduce<Vec3<S>>& gyro_rad_s, const NoDeduce<Vec3<S>>& accel_m_s2,
                  std::int64_t time_ns) {
  using estimator_internal::Reject;
  if (!AllFinite(gyro_rad_s) || !AllFinite(accel_m_s2)) {
    Reject(state, state.rejected_non_finite);
    return;
  }
  if (state.has_time && time_ns <= state.time_ns) {
    Reject(state, state.rejected_out_of_order);
    return;
  }
  const S dt_s = state.has_time ? S(time_ns - state.time_ns) * S(1e-9) : S(0);
  state.time_ns = time_ns;
  const bool had_time = state.has_time;
  state.has_time = true;
  state.angular_velocity_rad_s = gyro_rad_s - state.gyro_bias_rad_s;
  if (!state.initialized || !had_time) return;

  // Acceleration with the orientation at the start of the step, rotation integrated exactly for a
  // constant rate over the step: at 1 kHz the ordering error is far below the sensor noise.
  Vec3<S> accel_world_m_s2 = Rotate<S>(state.orientation, accel_m_s2 - state.accel_bias_m_s2);
  accel_world_m_s2.z() -= gains.gravity_m_s2;
  state.position_m += (state.velocity_m_s + S(0.5) * dt_s * accel_world_m_s2) * dt_s;
  state.velocity_m_s += accel_world_m_s2 * dt_s;
  state.orientation =
      Renormalized<S>(state.orientation * QuatExp<S>(state.angular_velocity_rad_s * dt_s));
  estimator_internal::PushHistory(state);
}

template <typename S, int N>
void CorrectWithVio(const EstimatorGains<S>& gains, EstimatorState<S, N>& state,
                    const NoDeduce<Vec3<S>>& position_m, const NoDeduce<Quat<S>>& orientation,
                    std::int64_t capture_time_ns) {
  using estimator_internal::HistoryAt;
  using estimator_internal::Reject;
  const S norm = orientation.norm();
  if (!AllFinite(position_m) || !AllFinite(orientation) || !(norm > S(0.5) && norm < S(1.5))) {
    Reject(state, state.rejected_non_finite);
    return;
  }
  const Quat<S> measured_q = Quat<S>(orientation.coeffs() / norm);

  if (!state.initialized) {
    // The first pose is taken as the state now (the latency error is v·latency, zero at rest).
    state.position_m = position_m;
    state.velocity_m_s.setZero();
    state.orientation = measured_q;
    state.gyro_bias_rad_s.setZero();
    state.accel_bias_m_s2.setZero();
    state.initialized = true;
    state.last_vio_capture_time_ns = capture_time_ns;
    state.history_count = 0;
    // Stamp the seed entry with the capture time (when older than now) so that the next pose,
    // captured one VIO period later but possibly before "now", still finds history around it.
    const std::int64_t now_ns = state.has_time ? state.time_ns : capture_time_ns;
    state.time_ns = std::min(capture_time_ns, now_ns);
    estimator_internal::PushHistory(state);
    state.time_ns = now_ns;
    state.has_time = true;
    return;
  }

  // Estimate at the capture time, interpolated between the two entries around it.
  const int count = state.history_count;
  if (count == 0 || capture_time_ns < HistoryAt(state, 0).time_ns) {
    Reject(state, state.rejected_stale_vio);
    return;
  }
  Vec3<S> position_then_m;
  Quat<S> orientation_then;
  int first_after_capture = count - 1;  // oldest entry a later, in-order pose can still read
  const EstimatorHistoryEntry<S>& newest = HistoryAt(state, count - 1);
  if (capture_time_ns >= newest.time_ns) {
    position_then_m = newest.position_m;
    orientation_then = newest.orientation;
  } else {
    int lo = 0;  // invariant: time(lo) <= capture < time(hi)
    int hi = count - 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (HistoryAt(state, mid).time_ns <= capture_time_ns ? lo : hi) = mid;
    }
    first_after_capture = lo;
    const EstimatorHistoryEntry<S>& a = HistoryAt(state, lo);
    const EstimatorHistoryEntry<S>& b = HistoryAt(state, hi);
    const S f = S(capture_time_ns - a.time_ns) / S(b.time_ns - a.time_ns);
    position_then_m = a.position_m + f * (b.position_m - a.position_m);
    // Normalised lerp: entries are 1 ms apart, so slerp's extra accuracy is not worth its trig.
    const S sign = a.orientation.dot(b.orientation) < S(0) ? S(-1) : S(1);
    orientation_then =
        Quat<S>(a.orientation.coeffs() * (S(1) - f) + b.orientation.coeffs() * (sign * f))
            .normalized();
  }

  const S nominal_s = gains.nominal_vio_period_s;
  S period_s = S(capture_time_ns - state.last_vio_capture_time_ns) * S(1e-9);
  if (!(period_s > S(0))) period_s = nominal_s;
  period_s = std::clamp(period_s, S(0.5) * nominal_s, S(2) * nominal_s);
  state.last_vio_capture_time_ns = std::max(state.last_vio_capture_time_ns, capture_time_ns);

  const Vec3<S> position_innovation_m = position_m - position_then_m;
  const Vec3<S> attitude_innovation_body =
      QuatErrorVector<S>(orientation_then.conjugate() * measured_q);

  const Vec3<S> delta_p_m = gains.position_gain * position_innovation_m;
  const Vec3<S> delta_v_m_s = (gains.velocity_gain / period_s) * position_innovation_m;
  const Quat<S> delta_q =
      QuatExp<S>(gains.attitude_gain * (orientation_then * attitude_innovation_body));
  const Vec3<S> bias_limit_a = Vec3<S>::Constant(gains.max_accel_bias_m_s2);
  const Vec3<S> bias_limit_g = Vec3<S>::Constant(gains.max_gyro_bias_rad_s);
  state.accel_bias_m_s2 = ClampSymmetric<S>(
      state.accel_bias_m_s2 - (gains.accel_bias_gain / (period_s * period_s)) *
                                  (orientation_then.conjugate() * position_innovation_m),
      bias_limit_a);
  state.gyro_bias_rad_s = ClampSymmetric<S>(
      state.gyro_bias_rad_s - (gains.gyro_bias_gain / period_s) * attitude_innovation_body,
      bias_limit_g);

  // Same shift for the current state and the stored trajectory from the capture time on; entries
  // before it are only read by a pose arriving out of order, and shifting them all would cost the
  // whole ring (~5 us) per VIO update instead of the latency's worth.
  const auto shift = [&](std::int64_t time_ns, Vec3<S>& p, Vec3<S>& v, Quat<S>& q) {
    const S since_capture_s = S(std::max<std::int64_t>(time_ns - capture_time_ns, 0)) * S(1e-9);
    p += delta_p_m + delta_v_m_s * since_capture_s;
    v += delta_v_m_s;
    q = delta_q * q;
  };
  for (int k = first_after_capture; k < count; ++k) {
    EstimatorHistoryEntry<S>& e = HistoryAt(state, k);
    shift(e.time_ns, e.position_m, e.velocity_m_s, e.orientation);
  }
  shift(state.time_ns, state.position_m, state.velocity_m_s, state.orientation);
  state.orientation.normalize();
}

}  // namespace hilrig::dut_fw
