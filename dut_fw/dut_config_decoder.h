// The DUT's reading of the DutConfig message (proto/hil_link.proto) into the parameters DutCore
// is built from: field by field as host/link/dut_config_codec.cc maps them, each double cast to the
// firmware's scalar, so a double build takes exactly the numbers the host's DutFirmware holds and
// a float build their nearest floats. A field the message leaves out is zero, as protobuf reads
// it. The shape is checked as the host checks it (a control period, flight and grasp firmware,
// six tactile nodes with ids 1..6 used once, nine values per matrix, a valid chip setting) and so
// is what would run silently wrong (a non-finite number, no zeroing samples, a zero sample age);
// the finer ranges host/link/firmware_check.h enforces are the sending runner's. Portable: no
// allocation, the outcome an enum.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "dut_fw/dut_core.h"
#include "dut_link/wire_codec.h"
#include "proto/hil_link_tags.h"

namespace hilrig::dut_fw {

namespace wire = dut_link::wire;  // the link's codec, which this decoder reads with

enum class ConfigRefusal : std::uint8_t {
  kNone,
  kMalformed,          // not a well-formed DutConfig message
  kBadControlPeriod,   // not positive and finite
  kNoFlightOrGrasp,    // either firmware missing
  kTactileNodeCount,   // not exactly six nodes
  kTactileNodeId,      // outside 1..6 or used twice
  kMatrixSize,         // a matrix without exactly nine values
  kChipSetting,        // gain_sel or resolution out of range
  kNonFiniteNumber,    // NaN or infinity where the firmware needs a number
  kTactileCountOrAge,  // zeroing_samples 0, or an age limit not positive
  kForceAverage,       // force_average_samples above kMaxForceAverageSamples
};

constexpr const char* Describe(ConfigRefusal refusal) {
  switch (refusal) {
    case ConfigRefusal::kNone:
      return "accepted";
    case ConfigRefusal::kMalformed:
      return "dut config is not a well-formed message";
    case ConfigRefusal::kBadControlPeriod:
      return "dut config control period must be positive and finite";
    case ConfigRefusal::kNoFlightOrGrasp:
      return "dut config without flight or grasp firmware";
    case ConfigRefusal::kTactileNodeCount:
      return "tactile firmware must have exactly 6 nodes";
    case ConfigRefusal::kTactileNodeId:
      return "tactile node ids must be 1..6, each used once";
    case ConfigRefusal::kMatrixSize:
      return "tactile node matrix without 9 values";
    case ConfigRefusal::kChipSetting:
      return "tactile firmware with an invalid chip setting";
    case ConfigRefusal::kNonFiniteNumber:
      return "dut config with a number that is not finite";
    case ConfigRefusal::kTactileCountOrAge:
      return "tactile zeroing_samples and age limits must be positive";
    case ConfigRefusal::kForceAverage:
      return "tactile force_average_samples must be at most 16";
  }
  return "refused";
}

template <typename S>
struct DutConfigOnTarget {
  DutCoreParams<S> params;
  double control_period_s = 0;
};

namespace dut_config_internal {

// The switches below map fields to members one line per field, as the message reads (clang-format
// would spread each over three lines).

// Keeps the first refusal; reads doubles and remembers whether any was not finite.
template <typename S>
struct Decoding {
  ConfigRefusal refusal = ConfigRefusal::kNone;
  bool non_finite = false;

  void Refuse(ConfigRefusal why) {
    if (refusal == ConfigRefusal::kNone) refusal = why;
  }
  S Real(wire::Reader& reader) {
    const double value = reader.Double();
    non_finite = non_finite || !std::isfinite(value);
    return S(value);
  }
  Vec3<S> Vector(wire::Reader& outer) {
    wire::Reader reader = outer.Message();
    Vec3<S> out = Vec3<S>::Zero();
    static_assert(proto_tags::Vector3::kY == proto_tags::Vector3::kX + 1 &&
                  proto_tags::Vector3::kZ == proto_tags::Vector3::kX + 2);
    while (const auto tag = reader.Next()) {
      if (tag->field >= proto_tags::Vector3::kX && tag->field <= proto_tags::Vector3::kZ) {
        out[tag->field - proto_tags::Vector3::kX] = Real(reader);
      }
    }
    if (!reader.ok()) Refuse(ConfigRefusal::kMalformed);
    return out;
  }
  Mat3<S> Matrix(wire::Reader& outer) {
    wire::Reader reader = outer.Message();
    std::array<double, 9> values{};
    std::size_t count = 0;
    while (const auto tag = reader.Next()) {
      if (tag->field == proto_tags::Matrix3::kRowMajor) reader.AppendDoubles(values, count);
    }
    if (reader.error() == wire::WireError::kTooManyValues || (reader.ok() && count != 9)) {
      Refuse(ConfigRefusal::kMatrixSize);
    } else if (!reader.ok()) {
      Refuse(ConfigRefusal::kMalformed);
    }
    Mat3<S> out;
    for (std::size_t i = 0; i < 9; ++i) {
      non_finite = non_finite || !std::isfinite(values[i]);
      out(int(i / 3), int(i % 3)) = S(values[i]);
    }
    return out;
  }
  void Check(const wire::Reader& reader) {
    if (!reader.ok()) Refuse(ConfigRefusal::kMalformed);
  }
};

// A field the message leaves out reads as zero, as in the host's codec; the structs' own defaults
// must not show through.
template <typename S>
void ZeroFlight(FlightControllerParams<S>& p) {
  const Vec3<S> zero = Vec3<S>::Zero();
  p.admittance = {zero, zero, zero};
  p.position = {zero, zero, S(0), S(0), S(0), S(0), S(0)};
  p.attitude = {zero, zero, zero, zero, zero, zero, S(0), zero};
  p.mixer = {S(0), S(0), S(0)};
  p.estimator = {S(0), S(0), S(0), S(0), S(0), S(0), S(0), S(0), S(0)};
  p.load_feedforward = false;
}

template <typename S>
void DecodeFlight(Decoding<S>& d, wire::Reader& outer, FlightControllerParams<S>& p) {
  namespace field = proto_tags::FlightFirmware;
  ZeroFlight(p);
  wire::Reader r = outer.Message();
  while (const auto tag = r.Next()) {
    // clang-format off
    switch (tag->field) {
      case field::kAdmittanceMassKg: p.admittance.mass_kg = d.Vector(r); break;
      case field::kAdmittanceDampingNSPerM: p.admittance.damping_n_s_per_m = d.Vector(r); break;
      case field::kAdmittanceStiffnessNPerM: p.admittance.stiffness_n_per_m = d.Vector(r); break;
      case field::kPositionKpPerS2: p.position.kp_per_s2 = d.Vector(r); break;
      case field::kPositionKvPerS: p.position.kv_per_s = d.Vector(r); break;
      case field::kPositionMassKg: p.position.mass_kg = d.Real(r); break;
      case field::kPositionGravityMS2: p.position.gravity_m_s2 = d.Real(r); break;
      case field::kPositionMaxTiltRad: p.position.max_tilt_rad = d.Real(r); break;
      case field::kPositionMinCollectiveThrustN:
        p.position.min_collective_thrust_n = d.Real(r); break;
      case field::kPositionMaxCollectiveThrustN:
        p.position.max_collective_thrust_n = d.Real(r); break;
      case field::kAttitudeKRPerS: p.attitude.k_r_per_s = d.Vector(r); break;
      case field::kAttitudeKPNmS: p.attitude.k_p_nm_s = d.Vector(r); break;
      case field::kAttitudeKINm: p.attitude.k_i_nm = d.Vector(r); break;
      case field::kAttitudeKDNmS2: p.attitude.k_d_nm_s2 = d.Vector(r); break;
      case field::kAttitudeMaxRateRadS: p.attitude.max_rate_rad_s = d.Vector(r); break;
      case field::kAttitudeIntegralLimitRad: p.attitude.integral_limit_rad = d.Vector(r); break;
      case field::kAttitudeDerivativeCutoffHz: p.attitude.derivative_cutoff_hz = d.Real(r); break;
      case field::kAttitudeInertiaKgM2: p.attitude.inertia_kg_m2 = d.Vector(r); break;
      case field::kMixerArmLengthM: p.mixer.arm_length_m = d.Real(r); break;
      case field::kMixerTorquePerThrustM: p.mixer.torque_per_thrust_m = d.Real(r); break;
      case field::kMixerMaxThrustPerRotorN: p.mixer.max_thrust_per_rotor_n = d.Real(r); break;
      case field::kEstimatorPositionGain: p.estimator.position_gain = d.Real(r); break;
      case field::kEstimatorVelocityGain: p.estimator.velocity_gain = d.Real(r); break;
      case field::kEstimatorAccelBiasGain: p.estimator.accel_bias_gain = d.Real(r); break;
      case field::kEstimatorAttitudeGain: p.estimator.attitude_gain = d.Real(r); break;
      case field::kEstimatorGyroBiasGain: p.estimator.gyro_bias_gain = d.Real(r); break;
      case field::kEstimatorGravityMS2: p.estimator.gravity_m_s2 = d.Real(r); break;
      case field::kEstimatorNominalVioPeriodS: p.estimator.nominal_vio_period_s = d.Real(r); break;
      case field::kEstimatorMaxGyroBiasRadS: p.estimator.max_gyro_bias_rad_s = d.Real(r); break;
      case field::kEstimatorMaxAccelBiasMS2: p.estimator.max_accel_bias_m_s2 = d.Real(r); break;
      case field::kLoadFeedforward: p.load_feedforward = r.Bool(); break;
      default:
        break;
    }
    // clang-format on
  }
  d.Check(r);
}

template <typename S>
void DecodeTactileNode(Decoding<S>& d, wire::Reader& outer, TactileNodeConfig<S>& node) {
  namespace field = proto_tags::TactileNodeFirmware;
  node = {0, Mat3<S>::Zero(), Mat3<S>::Zero(), Vec3<S>::Zero(), Vec3<S>::Zero()};
  wire::Reader r = outer.Message();
  bool rotation_seen = false;
  bool mounting_seen = false;
  while (const auto tag = r.Next()) {
    // clang-format off
    switch (tag->field) {
      case field::kNodeId: {
        const std::uint32_t id = r.Uint32();
        if (id > 255) d.Refuse(ConfigRefusal::kTactileNodeId);
        node.node_id = std::uint8_t(id);
        break;
      }
      case field::kRotationSensorFromReference:
        node.rotation_sensor_from_reference = d.Matrix(r);
        rotation_seen = true;
        break;
      case field::kRotationBodyFromSensor:
        node.rotation_body_from_sensor = d.Matrix(r);
        mounting_seen = true;
        break;
      case field::kContactNormalSensor: node.contact_normal_sensor = d.Vector(r); break;
      case field::kGainA: node.gain_a = d.Vector(r); break;
      default:
        break;
    }
    // clang-format on
  }
  d.Check(r);
  if (!rotation_seen || !mounting_seen) d.Refuse(ConfigRefusal::kMatrixSize);
}

template <typename S>
void DecodeTactile(Decoding<S>& d, wire::Reader& outer, TactileProcessorParams<S>& p) {
  namespace field = proto_tags::TactileFirmware;
  p.film = {S(0), S(0), S(0), S(0)};
  p.chip_setting = {0, 0};
  p.zeroing_samples = 0;
  p.compensation_enabled = false;
  p.max_reference_age_ns = 0;
  p.max_sample_age_ns = 0;
  p.force_average_samples = 0;
  wire::Reader r = outer.Message();
  std::size_t nodes = 0;
  std::uint32_t gain_sel = 0;
  std::uint32_t resolution = 0;
  while (const auto tag = r.Next()) {
    // clang-format off
    switch (tag->field) {
      case field::kNodes:
        if (nodes == p.nodes.size()) {
          d.Refuse(ConfigRefusal::kTactileNodeCount);
          r.Skip();
        } else {
          DecodeTactileNode(d, r, p.nodes[nodes]);
        }
        ++nodes;
        break;
      case field::kFilmK1: p.film.k1 = d.Real(r); break;
      case field::kFilmC1: p.film.c1 = d.Real(r); break;
      case field::kFilmK2: p.film.k2 = d.Real(r); break;
      case field::kFilmC2: p.film.c2 = d.Real(r); break;
      case field::kChipGainSel: gain_sel = r.Uint32(); break;
      case field::kChipResolution: resolution = r.Uint32(); break;
      case field::kZeroingSamples: p.zeroing_samples = r.Uint32(); break;
      case field::kCompensationEnabled: p.compensation_enabled = r.Bool(); break;
      case field::kMaxReferenceAgeNs: p.max_reference_age_ns = r.Int64(); break;
      case field::kMaxSampleAgeNs: p.max_sample_age_ns = r.Int64(); break;
      case field::kForceAverageSamples: p.force_average_samples = r.Uint32(); break;
      default:
        break;
    }
    // clang-format on
  }
  d.Check(r);
  if (nodes != p.nodes.size()) d.Refuse(ConfigRefusal::kTactileNodeCount);
  if (gain_sel > kMlx90393MaxGainSel || resolution > kMlx90393MaxResolution) {
    d.Refuse(ConfigRefusal::kChipSetting);
  }
  p.chip_setting = {std::uint8_t(gain_sel), std::uint8_t(resolution)};
  unsigned ids_seen = 0;
  for (const TactileNodeConfig<S>& node : p.nodes) {
    const unsigned bit = 1u << (node.node_id & 31);
    if (node.node_id < 1 || node.node_id > tactile_bus::kTactileNodeCount ||
        (ids_seen & bit) != 0) {
      d.Refuse(ConfigRefusal::kTactileNodeId);
    }
    ids_seen |= bit;
  }
  if (p.zeroing_samples == 0 || p.max_reference_age_ns <= 0 || p.max_sample_age_ns <= 0) {
    d.Refuse(ConfigRefusal::kTactileCountOrAge);
  }
  // Absent is zero on the wire: a runner that does not filter.
  if (p.force_average_samples == 0) p.force_average_samples = 1;
  if (p.force_average_samples > kMaxForceAverageSamples) d.Refuse(ConfigRefusal::kForceAverage);
}

// Infinite is the grasp firmware's "no travel hold" for the servo rate, so that one number may be
// +inf; every other must be finite.
template <typename S>
void DecodeGrasp(Decoding<S>& d, wire::Reader& outer, GraspAdmittanceParams<S>& p) {
  namespace field = proto_tags::GraspFirmware;
  p = {S(0), S(0), S(0), S(0), S(0), false, S(0), S(0)};
  wire::Reader r = outer.Message();
  while (const auto tag = r.Next()) {
    // clang-format off
    switch (tag->field) {
      case field::kMass: p.mass = d.Real(r); break;
      case field::kDamping: p.damping = d.Real(r); break;
      case field::kStiffness: p.stiffness = d.Real(r); break;
      case field::kOpenAngleRad: p.open_angle_rad = d.Real(r); break;
      case field::kClosedAngleRad: p.closed_angle_rad = d.Real(r); break;
      case field::kForceFeedback: p.force_feedback = r.Bool(); break;
      case field::kServoMaxRateRadS: {
        const double rate = r.Double();
        if (std::isnan(rate) || (std::isinf(rate) && rate < 0)) d.non_finite = true;
        p.servo_max_rate_rad_s = S(rate);
        break;
      }
      case field::kServoSettleS: p.servo_settle_s = d.Real(r); break;
      default:
        break;
    }
    // clang-format on
  }
  d.Check(r);
}

}  // namespace dut_config_internal

// Reads a DutConfig message's bytes into `out`; kNone when the DUT can be built from it. On a
// refusal `out` holds whatever was read and must not be used. O(message bytes), no allocation.
template <typename S>
ConfigRefusal DecodeDutConfig(std::span<const std::uint8_t> bytes, DutConfigOnTarget<S>& out) {
  namespace field = proto_tags::DutConfig;
  using dut_config_internal::Decoding;
  Decoding<S> d;
  out.control_period_s = 0;
  out.params.tactile.reset();
  out.params.external_force_in_position_loop = false;
  bool flight_seen = false;
  bool grasp_seen = false;
  wire::Reader r(bytes);
  while (const auto tag = r.Next()) {
    // clang-format off
    switch (tag->field) {
      case field::kFlight:
        dut_config_internal::DecodeFlight(d, r, out.params.flight);
        flight_seen = true;
        break;
      case field::kTactile:
        out.params.tactile.emplace();
        dut_config_internal::DecodeTactile(d, r, *out.params.tactile);
        break;
      case field::kGrasp:
        dut_config_internal::DecodeGrasp(d, r, out.params.grasp);
        grasp_seen = true;
        break;
      case field::kExternalForceInPositionLoop:
        out.params.external_force_in_position_loop = r.Bool(); break;
      case field::kControlPeriodS: out.control_period_s = r.Double(); break;
      default:
        break;  // the header, and fields this DUT does not know
    }
    // clang-format on
  }
  d.Check(r);
  if (d.refusal != ConfigRefusal::kNone) return d.refusal;
  if (!std::isfinite(out.control_period_s) || out.control_period_s <= 0) {
    return ConfigRefusal::kBadControlPeriod;
  }
  if (!flight_seen || !grasp_seen) return ConfigRefusal::kNoFlightOrGrasp;
  if (d.non_finite) return ConfigRefusal::kNonFiniteNumber;
  return ConfigRefusal::kNone;
}

}  // namespace hilrig::dut_fw
