// Removal of Earth's field from the tactile readings, and the no-load zero offset b of the force
// calibration.
//
// Earth's field (25–65 µT) is ~1 % of the film's field at the chip, but its projection onto a
// sensor changes by up to twice its magnitude as the vehicle rotates, which the decoder would read
// as force. Every sensor is rigidly mounted, so the Earth part of sensor i's reading is the
// unloaded reference sensor's reading rotated from the reference frame into sensor i's frame:
//   B̂_i = B_i − R_{Si←Sref} B_ref,
// with R_{Si←Sref} = R_{Si←B} R_{B←Sref} a constant of the airframe. Exact for a uniform field
// (Earth's, over a 10 cm frame); motor currents and the other films are not removed by this.
//
// Zero offset. The F/T jig gives a; b is then whatever makes the mean no-load force zero:
// b = −a ⊙ mean(S_no_load). The accumulator keeps a running sum (fixed size, no buffer), skips
// flagged decodes so that one singular or saturated sample cannot shift b, and counts them so the
// start-up check can refuse a window that was mostly rejected.
#pragma once

#include <cstdint>
#include <limits>

#include "dut_fw/mlx90393.h"
#include "dut_fw/tactile_decoding.h"
#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S>
Vec3<S> CompensateField(const Mat3<S>& rotation_sensor_from_reference,
                        const NoDeduce<Vec3<S>>& field_sensor_t,
                        const NoDeduce<Vec3<S>>& field_reference_t) {
  return field_sensor_t - rotation_sensor_from_reference * field_reference_t;
}

// As CompensateField, carrying the chip flags along: the result is saturated if either reading
// was (a clipped reference corrupts the compensation as much as a clipped sensor axis) and valid
// only if both were.
template <typename S>
FieldReading<S> CompensateReading(const Mat3<S>& rotation_sensor_from_reference,
                                  const FieldReading<S>& sensor, const FieldReading<S>& reference) {
  return {CompensateField<S>(rotation_sensor_from_reference, sensor.field_t, reference.field_t),
          sensor.saturated || reference.saturated, sensor.valid && reference.valid};
}

template <typename S>
struct ZeroOffsetState {
  Vec3<S> sum = Vec3<S>::Zero();  // of accepted S vectors
  std::uint32_t count = 0;        // accepted samples
  std::uint32_t rejected = 0;     // flagged samples skipped
};

template <typename S>
void AddNoLoadSample(ZeroOffsetState<S>& state, const SVector<S>& sample) {
  // A full counter would make the mean wrong rather than stop it; at 50 Hz that is 2.7 years of
  // no-load window, so saturating the counters is enough.
  constexpr std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
  if (!sample.ok() || !AllFinite(sample.s) || state.count == kMax) {
    if (state.rejected < kMax) ++state.rejected;
    return;
  }
  state.sum += sample.s;
  ++state.count;
}

// At least `min_samples` accepted samples (and never fewer than one).
template <typename S>
bool ZeroOffsetReady(const ZeroOffsetState<S>& state, NoDeduce<std::uint32_t> min_samples) {
  return state.count > 0 && state.count >= min_samples;
}

// b such that a ⊙ mean(S) + b = 0. NaN before any sample was accepted: a b read too early must
// fail loudly (DecodeForce reports it as non-finite) rather than pass for a zero offset.
template <typename S>
Vec3<S> ZeroOffset(const ZeroOffsetState<S>& state, const NoDeduce<Vec3<S>>& a) {
  if (state.count == 0) return Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
  return -a.cwiseProduct(state.sum / S(state.count));
}

}  // namespace hilrig::dut_fw
