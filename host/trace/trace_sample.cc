#include "host/trace/trace_sample.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hilrig::host {
namespace {

Eigen::Vector3d PositionError(const TraceSample& s) { return s.position_m - s.reference_m; }

double PositionErrorM(const TraceSample& s) { return PositionError(s).norm(); }
double HorizontalErrorM(const TraceSample& s) { return PositionError(s).head<2>().norm(); }
double AltitudeErrorM(const TraceSample& s) { return std::abs(PositionError(s).z()); }
double AltitudeM(const TraceSample& s) { return s.position_m.z(); }
double TiltDeg(const TraceSample& s) { return s.tilt_deg; }
double SpeedMS(const TraceSample& s) { return s.velocity_m_s.norm(); }
double TactileForceN(const TraceSample& s) { return s.tactile_force_max_n; }
double TactileForceErrorN(const TraceSample& s) { return s.tactile_force_error_max_n; }
double GraspForceN(const TraceSample& s) { return s.grasp_force_n; }
double GraspForceEstimateN(const TraceSample& s) { return s.grasp_force_estimate_n; }
double GraspForceErrorN(const TraceSample& s) {
  return std::abs(s.grasp_force_estimate_n - s.grasp_force_n);
}
double LoadN(const TraceSample& s) { return s.load_n; }
double LoadEstimateErrorN(const TraceSample& s) { return std::abs(s.load_estimate_n - s.load_n); }
double ObjectDamaged(const TraceSample& s) { return s.object_damaged ? 1.0 : 0.0; }
double ObjectDropped(const TraceSample& s) { return s.object_dropped ? 1.0 : 0.0; }
double ServoAngleRad(const TraceSample& s) { return s.servo_angle_rad; }
double GroundForceN(const TraceSample& s) { return s.ground_force_n; }
double ObjectHeld(const TraceSample& s) { return s.object_held ? 1.0 : 0.0; }
double SlipSpeedMS(const TraceSample& s) { return s.slip_speed_m_s; }
bool AllFinite(const std::array<double, kTracePadCount>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

double NoSignal(const TraceSample&) { return std::numeric_limits<double>::quiet_NaN(); }

// One reader per pad and per-pad field, so that a check still calls a plain function per sample.
template <std::array<double, kTracePadCount> TraceSample::*kField, std::size_t... kPads>
constexpr std::array<SignalReader, kTracePadCount> PadReaders(std::index_sequence<kPads...>) {
  return {[](const TraceSample& s) { return (s.*kField)[kPads]; }...};
}
template <std::array<double, kTracePadCount> TraceSample::*kField>
constexpr std::array<SignalReader, kTracePadCount> kPadReaders =
    PadReaders<kField>(std::make_index_sequence<kTracePadCount>());

SignalReader PadReaderFor(proto::Signal signal, std::optional<std::size_t> pad) {
  if (!pad || *pad >= kTracePadCount) return NoSignal;
  switch (signal) {
    case proto::PAD_FORCE_N:
      return kPadReaders<&TraceSample::pad_force_n>[*pad];
    case proto::PAD_FORCE_ESTIMATE_N:
      return kPadReaders<&TraceSample::pad_force_estimate_n>[*pad];
    case proto::PAD_FORCE_ERROR_N:
      return kPadReaders<&TraceSample::pad_force_error_n>[*pad];
    default:
      return NoSignal;
  }
}

}  // namespace

bool IsPadSignal(proto::Signal signal) {
  return signal == proto::PAD_FORCE_N || signal == proto::PAD_FORCE_ESTIMATE_N ||
         signal == proto::PAD_FORCE_ERROR_N;
}

SignalReader SignalReaderFor(proto::Signal signal, std::optional<std::size_t> pad) {
  if (IsPadSignal(signal)) return PadReaderFor(signal, pad);
  switch (signal) {
    case proto::POSITION_ERROR_M:
      return PositionErrorM;
    case proto::HORIZONTAL_ERROR_M:
      return HorizontalErrorM;
    case proto::ALTITUDE_ERROR_M:
      return AltitudeErrorM;
    case proto::ALTITUDE_M:
      return AltitudeM;
    case proto::TILT_DEG:
      return TiltDeg;
    case proto::SPEED_M_S:
      return SpeedMS;
    case proto::TACTILE_FORCE_N:
      return TactileForceN;
    case proto::TACTILE_FORCE_ERROR_N:
      return TactileForceErrorN;
    case proto::GRASP_FORCE_N:
      return GraspForceN;
    case proto::GRASP_FORCE_ESTIMATE_N:
      return GraspForceEstimateN;
    case proto::GRASP_FORCE_ERROR_N:
      return GraspForceErrorN;
    case proto::LOAD_N:
      return LoadN;
    case proto::LOAD_ESTIMATE_ERROR_N:
      return LoadEstimateErrorN;
    case proto::OBJECT_DAMAGED:
      return ObjectDamaged;
    case proto::OBJECT_DROPPED:
      return ObjectDropped;
    case proto::SERVO_ANGLE_RAD:
      return ServoAngleRad;
    case proto::GROUND_FORCE_N:
      return GroundForceN;
    case proto::OBJECT_HELD:
      return ObjectHeld;
    case proto::SLIP_SPEED_M_S:
      return SlipSpeedMS;
    default:
      return NoSignal;
  }
}

double SignalValue(const TraceSample& sample, proto::Signal signal,
                   std::optional<std::size_t> pad) {
  return SignalReaderFor(signal, pad)(sample);
}

bool AllSignalsFinite(const TraceSample& sample) {
  // The fields every signal reads, checked once each rather than signal by signal. The derived
  // signals are finite exactly when what they are computed from is: a norm when its squared norm
  // is (the square root of a finite non-negative number is finite, and the squared norm overflows
  // exactly where the norm would), |a - b| when a - b is (which also covers a and b alone: a
  // difference with a non-finite operand is never finite), and the horizontal and altitude errors
  // whenever the whole position error is. The flags are 0 or 1.
  static_assert(proto::Signal_ARRAYSIZE == 23,
                "a new Signal must be covered here (and in SignalReaderFor)");
  const Eigen::Vector3d error_m = PositionError(sample);
  return std::isfinite(error_m.squaredNorm()) && std::isfinite(sample.position_m.z()) &&
         std::isfinite(sample.tilt_deg) && std::isfinite(sample.velocity_m_s.squaredNorm()) &&
         std::isfinite(sample.tactile_force_max_n) &&
         std::isfinite(sample.tactile_force_error_max_n) &&
         std::isfinite(sample.grasp_force_estimate_n - sample.grasp_force_n) &&
         std::isfinite(sample.load_estimate_n - sample.load_n) &&
         std::isfinite(sample.servo_angle_rad) && std::isfinite(sample.ground_force_n) &&
         std::isfinite(sample.slip_speed_m_s) && AllFinite(sample.pad_force_n) &&
         AllFinite(sample.pad_force_estimate_n) && AllFinite(sample.pad_force_error_n);
}

}  // namespace hilrig::host
