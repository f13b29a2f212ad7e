// The flight controller's tactile front end: raw MLX90393 result words of the six tactile nodes
// (CAN node ids 1..6) and of the unloaded reference magnetometer (node 7), as they arrive, turned
// into the two quantities the controllers consume -- the external force in the body frame,
//   f_body = Σ_i R_BSi f̂_i,
// for the admittance loop, and the grasp force
//   f̂_g = Σ_i |f̂_i · n̂_i|
// for the servo's grasp admittance (docs/design.md sections 1 and 4). Per tactile sample: codes ->
// tesla (mlx90393.h), minus the latest reference sample rotated into the node's frame
// (geomagnetic_compensation.h), -> S -> f = a ⊙ S + b (tactile_decoding.h) -> the mean of the
// node's last `force_average_samples` forces (force_average.h; 1 = none). The offset b is found
// on the vehicle itself by no-load averaging over the first `zeroing_samples` valid samples of each
// node, because it drifts with the film's mounting and temperature and the F/T jig only gives a.
//
// Sample bookkeeping, per node and for the reference:
// - Sequence counters are uint8 and wrap; 255 -> 0 is the normal successor. A jump counts the
//   missed samples in `sequence_gaps` (a node that rebooted or a frame delivered out of order
//   shows up as a large gap; both are worth seeing in a report). The same counter twice in a row
//   is a duplicate (a CAN retransmission or a bridge that forwarded twice): it is counted in
//   `duplicates`, not in `sequence_gaps`, and is otherwise ignored, so no sample is decoded or
//   averaged into b twice.
// - `samples` counts every non-duplicate sample; `flagged` those of them that gave no force
//   (saturated chip or node, singular decode, invalid chip setting, stale or missing reference);
//   `stale_reference` those of the flagged that were rejected for the reference alone.
// - A flagged sample keeps the node's previous force (the controllers should not see a step to
//   zero for one bad sample) but records why in last_status. DecodeStatus has no value for a
//   stale reference, so such a sample sets kNonFiniteInput (an unknown reference is, to the
//   compensation, a NaN one) together with last_reference_stale; TactileNodeStatusName tells the
//   two apart for logs.
// - A node contributes to the sums only when zeroed and when its last force-producing sample is no
//   older than max_sample_age_ns. Freshness is measured from the last good sample, not the last
//   frame, so a node that keeps sending only saturated samples also drops out instead of holding
//   its last force forever.
//
// Nothing here reads a clock: every entry point takes the time of the event, so a run replays
// exactly. No NaN or Inf leaves the module: forces are only stored when ForceFromS found them
// finite, and a node whose configured rotation or normal would make its contribution non-finite
// is left out of the sums.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "dut_fw/force_average.h"
#include "dut_fw/geomagnetic_compensation.h"
#include "dut_fw/mlx90393.h"
#include "dut_fw/tactile_decoding.h"
#include "dut_fw/types.h"
#include "protocol/tactile_bus.h"

namespace hilrig::dut_fw {

// The longest force average the firmware keeps (fixed storage per node).
inline constexpr std::uint32_t kMaxForceAverageSamples = 16;

template <typename S>
struct TactileNodeConfig {
  std::uint8_t node_id = 0;                                      // 1..6; 0 = slot unused
  Mat3<S> rotation_sensor_from_reference = Mat3<S>::Identity();  // R_{Si<-Sref}
  Mat3<S> rotation_body_from_sensor = Mat3<S>::Identity();       // R_BSi
  Vec3<S> contact_normal_sensor = Vec3<S>::UnitZ();              // unit, sensor frame
  Vec3<S> gain_a = Vec3<S>::Zero();                              // from the F/T jig
};

template <typename S>
struct TactileProcessorParams {
  std::array<TactileNodeConfig<S>, tactile_bus::kTactileNodeCount> nodes;
  // Zero by default: every decode is then singular and flagged, so forgetting the film's
  // calibration cannot pass for a working sensor (nor silently fall back to the paper's film).
  FilmConstants<S> film{S(0), S(0), S(0), S(0)};
  Mlx90393Setting chip_setting{7, 0};
  std::uint32_t zeroing_samples = 50;              // 1 s at 50 Hz
  bool compensation_enabled = true;                // false: decode the raw field (the ablation)
  std::int64_t max_reference_age_ns = 60'000'000;  // older reference => sample flagged stale
  std::int64_t max_sample_age_ns = 60'000'000;     // older last force => node out of the sums
  // Mean of the last n decoded forces per node, 1..kMaxForceAverageSamples; 1 = no filter. It
  // divides the chip's noise by sqrt(n) and delays a force step by (n - 1) / 2 sample periods.
  std::uint32_t force_average_samples = 1;
};

template <typename S>
struct TactileNodeState {
  ZeroOffsetState<S> zero;
  Vec3<S> offset_b = Vec3<S>::Zero();  // valid once zeroed
  bool zeroed = false;
  Vec3<S> force_sensor_n = Vec3<S>::Zero();  // last good force, sensor frame; zero until zeroed
  ForceAverage<S, int(kMaxForceAverageSamples)> average;  // over force_average_samples
  DecodeStatus last_status = DecodeStatus::kOk;
  bool last_reference_stale = false;  // last sample rejected for a missing or old reference
  std::int64_t last_sample_ns = 0;    // last non-duplicate sample, good or flagged
  bool has_sample = false;
  std::int64_t last_force_ns = 0;  // last sample that produced force_sensor_n
  bool has_force = false;
  std::uint8_t last_sequence = 0;
  bool has_sequence = false;
  std::uint32_t samples = 0;
  std::uint32_t flagged = 0;
  std::uint32_t sequence_gaps = 0;  // missed samples
  std::uint32_t duplicates = 0;
  std::uint32_t stale_reference = 0;
};

template <typename S>
struct TactileProcessorState {
  std::array<TactileNodeState<S>, tactile_bus::kTactileNodeCount> nodes;
  FieldReading<S> reference{Vec3<S>::Zero(), false, false};
  std::int64_t reference_time_ns = 0;
  bool has_reference = false;
  std::uint8_t reference_last_sequence = 0;
  bool reference_has_sequence = false;
  std::uint32_t reference_samples = 0;
  std::uint32_t reference_sequence_gaps = 0;
  std::uint32_t reference_duplicates = 0;
  std::uint32_t unknown_nodes = 0;  // tactile samples whose node id no slot is configured for
};

template <typename S>
struct TactileSummary {
  Vec3<S> external_force_body_n = Vec3<S>::Zero();
  S grasp_force_n = S(0);
  std::uint8_t nodes_contributing = 0;
  bool ready = false;              // every node zeroed and fresh
  S max_force_magnitude_n = S(0);  // largest |f_i| among contributing nodes
};

namespace tactile_processor_internal {

inline void SaturatingAdd(std::uint32_t& counter, std::uint32_t amount) {
  constexpr std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
  counter = amount > kMax - counter ? kMax : counter + amount;
}

// |a − b| without signed overflow (exact: the true difference always fits in 64 unsigned bits).
// Absolute, because a reference or sample stamped far in the future is as unusable as an old one.
inline std::uint64_t AbsDiffNs(std::int64_t a, std::int64_t b) {
  return a >= b ? std::uint64_t(a) - std::uint64_t(b) : std::uint64_t(b) - std::uint64_t(a);
}

inline bool OlderThan(std::int64_t a, std::int64_t b, std::int64_t max_age_ns) {
  return max_age_ns < 0 || AbsDiffNs(a, b) > std::uint64_t(max_age_ns);
}

// False for a duplicate (caller drops the sample); otherwise records the sequence and counts the
// samples missed since the previous one.
inline bool AcceptSequence(std::uint8_t sequence, std::uint8_t& last, bool& has_last,
                           std::uint32_t& gaps, std::uint32_t& duplicates) {
  if (has_last) {
    if (sequence == last) {
      SaturatingAdd(duplicates, 1);
      return false;
    }
    SaturatingAdd(gaps, std::uint8_t(sequence - last - 1));  // modulo 256: 255 -> 0 is no gap
  }
  last = sequence;
  has_last = true;
  return true;
}

}  // namespace tactile_processor_internal

// Slot of `node_id` in params.nodes, or -1. The first matching slot wins; TactileParamsValid
// rejects configurations where that matters.
template <typename S>
int FindTactileNode(const TactileProcessorParams<S>& params, NoDeduce<std::uint8_t> node_id) {
  if (node_id == 0) return -1;
  for (std::size_t i = 0; i < tactile_bus::kTactileNodeCount; ++i) {
    if (params.nodes[i].node_id == node_id) return int(i);
  }
  return -1;
}

// A start-up check for the integrator: ids 1..6 each used once, finite configuration, a real chip
// setting and positive windows. The step functions stay NaN-free without it; it only turns a
// misconfiguration into one early refusal instead of a processor that never becomes ready.
template <typename S>
bool TactileParamsValid(const TactileProcessorParams<S>& params) {
  const FilmConstants<S>& film = params.film;
  if (!std::isfinite(film.k1) || !std::isfinite(film.c1) || !std::isfinite(film.k2) ||
      !std::isfinite(film.c2) || film.k1 == S(0) || film.k2 == S(0)) {
    return false;
  }
  if (!IsValidSetting(params.chip_setting) || params.zeroing_samples == 0 ||
      params.max_reference_age_ns <= 0 || params.max_sample_age_ns <= 0 ||
      params.force_average_samples == 0 || params.force_average_samples > kMaxForceAverageSamples) {
    return false;
  }
  unsigned seen = 0;
  for (const TactileNodeConfig<S>& node : params.nodes) {
    if (node.node_id < 1 || node.node_id > tactile_bus::kTactileNodeCount) return false;
    const unsigned bit = 1u << node.node_id;
    if (seen & bit) return false;
    seen |= bit;
    if (!node.rotation_sensor_from_reference.allFinite() ||
        !node.rotation_body_from_sensor.allFinite() || !AllFinite(node.contact_normal_sensor) ||
        !AllFinite(node.gain_a)) {
      return false;
    }
  }
  return true;
}

// Log name of a node's last sample status: "stale_reference" where DecodeStatus cannot say it.
template <typename S>
const char* TactileNodeStatusName(const TactileNodeState<S>& node) {
  return node.last_reference_stale ? "stale_reference" : DecodeStatusName(node.last_status);
}

// A reference magnetometer sample. Saturation (reported by the node or at a code rail) is kept in
// the stored reading rather than skipped: the newest reference is the one that matches the
// tactile samples that follow, and CompensateReading then flags them as saturated instead of
// compensating them with an older, mismatched field.
template <typename S>
void OnReferenceSample(const TactileProcessorParams<S>& params, TactileProcessorState<S>& state,
                       const NoDeduce<std::array<std::uint16_t, 3>>& codes,
                       NoDeduce<std::uint8_t> sequence, NoDeduce<bool> node_reports_saturation,
                       NoDeduce<std::int64_t> time_ns) {
  namespace internal = tactile_processor_internal;
  if (!internal::AcceptSequence(sequence, state.reference_last_sequence,
                                state.reference_has_sequence, state.reference_sequence_gaps,
                                state.reference_duplicates)) {
    return;
  }
  internal::SaturatingAdd(state.reference_samples, 1);
  state.reference = CodesToTesla<S>(params.chip_setting, codes);
  state.reference.saturated = state.reference.saturated || node_reports_saturation;
  state.reference_time_ns = time_ns;
  state.has_reference = true;
}

// A tactile sample from node `node_id`; an id no slot is configured for is counted in
// unknown_nodes and otherwise ignored.
template <typename S>
void OnTactileSample(const TactileProcessorParams<S>& params, TactileProcessorState<S>& state,
                     NoDeduce<std::uint8_t> node_id,
                     const NoDeduce<std::array<std::uint16_t, 3>>& codes,
                     NoDeduce<std::uint8_t> sequence, NoDeduce<bool> node_reports_saturation,
                     NoDeduce<std::int64_t> time_ns) {
  namespace internal = tactile_processor_internal;
  const int slot = FindTactileNode(params, node_id);
  if (slot < 0) {
    internal::SaturatingAdd(state.unknown_nodes, 1);
    return;
  }
  const TactileNodeConfig<S>& config = params.nodes[std::size_t(slot)];
  TactileNodeState<S>& node = state.nodes[std::size_t(slot)];
  if (!internal::AcceptSequence(sequence, node.last_sequence, node.has_sequence, node.sequence_gaps,
                                node.duplicates)) {
    return;
  }
  internal::SaturatingAdd(node.samples, 1);
  node.last_sample_ns = time_ns;
  node.has_sample = true;

  FieldReading<S> reading = CodesToTesla<S>(params.chip_setting, codes);
  reading.saturated = reading.saturated || node_reports_saturation;
  // Compensating with a reference from another attitude would turn the rotation since then into
  // force, so an old (or absent) reference rejects the sample rather than being used.
  const bool stale = params.compensation_enabled &&
                     (!state.has_reference || internal::OlderThan(time_ns, state.reference_time_ns,
                                                                  params.max_reference_age_ns));
  SVector<S> s{Vec3<S>::Zero(), DecodeStatus::kNonFiniteInput};
  if (!stale) {
    if (params.compensation_enabled) {
      reading =
          CompensateReading<S>(config.rotation_sensor_from_reference, reading, state.reference);
    }
    s = ComputeS<S>(params.film, reading);
  }
  node.last_reference_stale = stale;
  node.last_status = s.status;
  const auto flag = [&node, stale] {
    // The mean restarts after a gap rather than mixing forces from before it.
    node.average.Reset();
    internal::SaturatingAdd(node.flagged, 1);
    if (stale) internal::SaturatingAdd(node.stale_reference, 1);
  };

  if (!node.zeroed) {
    // The accumulator counts flagged samples in zero.rejected and leaves them out of b.
    AddNoLoadSample(node.zero, s);
    if (!s.ok()) return flag();
    if (!ZeroOffsetReady(node.zero, params.zeroing_samples)) return;
    const Vec3<S> b = ZeroOffset(node.zero, config.gain_a);
    if (!AllFinite(b)) {
      // Only a non-finite gain_a gets here; the node stays unzeroed (never ready) and says why.
      node.last_status = DecodeStatus::kNonFiniteInput;
      return flag();
    }
    node.offset_b = b;
    node.zeroed = true;
    // Falls through: the sample that completes the window is decoded with its own b, so the node
    // contributes from this sample on.
  }

  const ForceResult<S> force = ForceFromS<S>(ForceCalibration<S>{config.gain_a, node.offset_b}, s);
  node.last_status = force.status;
  if (!force.ok()) return flag();
  if (node.average.samples() != int(params.force_average_samples)) {
    node.average = ForceAverage<S, int(kMaxForceAverageSamples)>(int(params.force_average_samples));
  }
  node.force_sensor_n = node.average.Add(force.force_n);
  node.last_force_ns = time_ns;
  node.has_force = true;
}

// The sums over the nodes that are zeroed and fresh at `now_ns`.
template <typename S>
TactileSummary<S> SummarizeTactile(const TactileProcessorParams<S>& params,
                                   const TactileProcessorState<S>& state,
                                   NoDeduce<std::int64_t> now_ns) {
  TactileSummary<S> summary;
  bool all_ready = true;
  for (std::size_t i = 0; i < tactile_bus::kTactileNodeCount; ++i) {
    const TactileNodeConfig<S>& config = params.nodes[i];
    const TactileNodeState<S>& node = state.nodes[i];
    const bool fresh = node.zeroed && node.has_force &&
                       !tactile_processor_internal::OlderThan(now_ns, node.last_force_ns,
                                                              params.max_sample_age_ns);
    if (!fresh) {
      all_ready = false;
      continue;
    }
    const Vec3<S> force_body_n = config.rotation_body_from_sensor * node.force_sensor_n;
    const S grasp_n = std::abs(node.force_sensor_n.dot(config.contact_normal_sensor));
    const S magnitude_n = node.force_sensor_n.norm();
    if (!AllFinite(force_body_n) || !std::isfinite(grasp_n) || !std::isfinite(magnitude_n)) {
      all_ready = false;
      continue;
    }
    summary.external_force_body_n += force_body_n;
    summary.grasp_force_n += grasp_n;
    if (magnitude_n > summary.max_force_magnitude_n) summary.max_force_magnitude_n = magnitude_n;
    ++summary.nodes_contributing;
  }
  summary.ready = all_ready;
  return summary;
}

// The last time up to which SummarizeTactile gives the answer it gives at `now_ns` if no sample
// arrives in between: the moment the first contributing node goes stale. A controller stepping
// faster than its sensors sample can keep the summary until then instead of re-summing six nodes
// every step. A sample stamped after `now_ns` makes it `now_ns` (nothing to keep).
template <typename S>
std::int64_t TactileSummaryValidUntil(const TactileProcessorParams<S>& params,
                                      const TactileProcessorState<S>& state,
                                      NoDeduce<std::int64_t> now_ns) {
  std::int64_t until = std::numeric_limits<std::int64_t>::max();
  for (const TactileNodeState<S>& node : state.nodes) {
    if (!node.zeroed || !node.has_force) continue;
    if (node.last_force_ns > now_ns) return now_ns;
    if (tactile_processor_internal::OlderThan(now_ns, node.last_force_ns,
                                              params.max_sample_age_ns)) {
      continue;  // already stale; only a new sample brings it back
    }
    until = std::min(until, node.last_force_ns + params.max_sample_age_ns);
  }
  return until;
}

}  // namespace hilrig::dut_fw
