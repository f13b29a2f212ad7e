// Force decoding of the magnetic tactile sensors (docs/design.md section 4): the field at the Hall
// chip, already compensated for Earth's field, is mapped to the feature vector S(B), and the force
// is f = a ⊙ S + b with per-sensor calibration a, b. The published S is a closed-form expression
// with divisions by Bz' and Bz'' and an arctangent whose branch jumps; this header evaluates an
// algebraically equal form that stays continuous wherever the published one is defined and
// reports every point where it is not, so the controller never consumes a NaN, an Inf, or a value
// that rounding or a sign flip of noise has thrown to the other side of a branch cut.
//
// With Bz' = k1 Bz + c1 and Bz'' = k2 Bz + c2, the printed formulas are
//   S_x = atan( Bx / (Bz' − (Bz'² − (By² − Bx²)) / (2 Bz')) )
//   S_y = atan( By / (Bz' − (Bz'² + (By² − Bx²)) / (2 Bz')) )
//   S_z = ln( sqrt( (Bz'' − (Bz''² + (By² − Bx²)) / (2 Bz''))² + By² ) )
// The paper prints `Bz'' + (By² − Bx²)` inside S_z; tesla plus tesla² is dimensionally wrong and
// the S_x / S_y pattern has the square, so the square is used here.
//
// Rearrangement. Over the common denominator 2 Bz':
//   Bz' − (Bz'² − By² + Bx²) / (2 Bz') = (Bz'² + By² − Bx²) / (2 Bz'),
// so S_x = atan( 2 Bx Bz' / (Bz'² + By² − Bx²) ), and likewise
//    S_y = atan( 2 By Bz' / (Bz'² + Bx² − By²) ).
// Both are evaluated as atan2(numerator, denominator) with Bz' in the numerator. That equals the
// printed value wherever the printed denominator is positive (the whole working volume) and, unlike
// atan, passes continuously through ±π/2 when the denominator crosses zero (|Bx| reaching
// sqrt(Bz'² + By²)). Keeping Bz' in the numerator matters: atan2(Bx, (Bz'² + By² − Bx²) / (2 Bz')),
// the obvious transcription, has a negative second argument for Bz' < 0 and jumps from +π to −π
// as Bx passes zero -- in the middle of the working volume if the film's Bz is negative. Here the
// only cut left is at Bz' = 0, which is reported.
// For S_z, Bz'' − (Bz''² + By² − Bx²) / (2 Bz'') = (Bz''² + Bx² − By²) / (2 Bz'') =: P, hence
//   S_z = ln sqrt( P² + By² ) = ½ ln( P² + By² ),
// one logarithm and no square root. P² + By² = |(Bz'' + i By)² + Bx²|² / (2 Bz'')², and that
// modulus is ≥ 0.75 Bz''² (the real part is ≥ 0.75 Bz''² when |By| ≤ |Bz''| / 2, the imaginary
// part ≥ Bz''² otherwise), so P² + By² ≥ 0.14 Bz''² > 0 whenever Bz'' is nonzero: no log of zero,
// and with |Bz''| ≥ kSingularFieldT no float underflow. P is at most |B|² / (2 kSingularFieldT),
// so P² overflows float only for film constants absurd enough to overflow Bz''² as well (the
// final finiteness check flags both).
//
// Reported instead of computed (S is then zero and must not be used):
// - kNonFiniteInput: a NaN or Inf in the field or the film constants.
// - kOutOfRange: a component above 1 T. The MLX90393 cannot report more than ~0.11 T at any
//   setting, so such a value is a unit mistake (mT or µT passed as T), not a field. Also used if
//   absurd film constants overflow the arithmetic.
// - kIndeterminate: Bz' or Bz'' singular (below) with Bx and By also below the same threshold: the
//   printed expressions are 0/0 there and the limit depends on the direction of approach.
// - kBzPrimeSingular / kBzDoublePrimeSingular: |Bz'| or |Bz''| below kSingularFieldT = 1e-7 T.
//   That is below one LSB of the MLX90393's finest setting (0.150 µT x/y, 0.242 µT z, and Bz' moves
//   by k1 × 0.242 ≈ 0.55 µT per z LSB), so the chip cannot tell such a Bz' from zero and its
//   sign, which selects the branch of S_x and S_y, is noise. The working volume has |Bz'| and
//   |Bz''| of several mT, four orders of magnitude above. The threshold also keeps Bz'², Bz''² and
//   the hypot in S_z (≥ 0.75 Bz''², see above) far from float underflow.
// - kSaturated: only from the FieldReading overloads, when the chip reported an axis at a rail.
//
// A magnet mounted upside down (all field signs reversed) is not detected: S depends on B only
// through squares, |Bz''| and products of Bx, By with Bz', Bz'', so ComputeS(k, c, −B) equals
// ComputeS(k, −c, B) exactly -- S(B) except through the offsets c. The decode stays finite, and
// flagged only where the offsets move Bz' or Bz'' onto a singularity; a flipped magnet shows up
// as a calibration that does not fit, not here.
#pragma once

#include <cmath>
#include <cstdint>

#include "dut_fw/mlx90393.h"
#include "dut_fw/types.h"

namespace hilrig::dut_fw {

enum class DecodeStatus : std::uint8_t {
  kOk,
  kNonFiniteInput,
  kSaturated,
  kBzPrimeSingular,
  kBzDoublePrimeSingular,
  kIndeterminate,
  kOutOfRange,
};

// Stable snake_case names for logs, reports and the CLI.
constexpr const char* DecodeStatusName(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::kOk:
      return "ok";
    case DecodeStatus::kNonFiniteInput:
      return "non_finite_input";
    case DecodeStatus::kSaturated:
      return "saturated";
    case DecodeStatus::kBzPrimeSingular:
      return "bz_prime_singular";
    case DecodeStatus::kBzDoublePrimeSingular:
      return "bz_double_prime_singular";
    case DecodeStatus::kIndeterminate:
      return "indeterminate";
    case DecodeStatus::kOutOfRange:
      return "out_of_range";
  }
  return "unknown";
}

// |Bz'| or |Bz''| below this is treated as zero (see the header comment), tesla.
template <typename S>
inline constexpr S kSingularFieldT = S(1e-7);
// Any field component above this is a unit mistake, tesla.
template <typename S>
inline constexpr S kMaxFieldT = S(1);

template <typename S>
struct SVector {
  Vec3<S> s;  // (S_x rad, S_y rad, S_z dimensionless log); zero unless ok()
  DecodeStatus status;
  bool ok() const { return status == DecodeStatus::kOk; }
};

// Per-film constants of Bz' = k1 Bz + c1, Bz'' = k2 Bz + c2 (c in tesla).
template <typename S>
struct FilmConstants {
  S k1, c1, k2, c2;

  // The paper's values for its film. The rig's emulated sensors get theirs from the calibration
  // jigs; these are for tests and as a starting point.
  static FilmConstants Published() {
    return {S(2.27851), S(0.0010535), S(0.878725), S(-0.0000785667)};
  }
};

template <typename S>
SVector<S> ComputeS(const FilmConstants<S>& film, const NoDeduce<Vec3<S>>& field_t) {
  const auto flagged = [](DecodeStatus status) { return SVector<S>{Vec3<S>::Zero(), status}; };
  using std::abs;
  if (!AllFinite(field_t) || !std::isfinite(film.k1) || !std::isfinite(film.c1) ||
      !std::isfinite(film.k2) || !std::isfinite(film.c2)) {
    return flagged(DecodeStatus::kNonFiniteInput);
  }
  if (field_t.cwiseAbs().maxCoeff() > kMaxFieldT<S>) return flagged(DecodeStatus::kOutOfRange);

  const S bx = field_t.x(), by = field_t.y(), bz = field_t.z();
  const S bz1 = film.k1 * bz + film.c1;  // Bz'
  const S bz2 = film.k2 * bz + film.c2;  // Bz''
  if (!std::isfinite(bz1) || !std::isfinite(bz2)) return flagged(DecodeStatus::kOutOfRange);

  const S eps = kSingularFieldT<S>;
  const bool bz1_singular = abs(bz1) < eps;
  const bool bz2_singular = abs(bz2) < eps;
  if ((bz1_singular || bz2_singular) && abs(bx) < eps && abs(by) < eps) {
    return flagged(DecodeStatus::kIndeterminate);
  }
  if (bz1_singular) return flagged(DecodeStatus::kBzPrimeSingular);
  if (bz2_singular) return flagged(DecodeStatus::kBzDoublePrimeSingular);

  const S bx2 = bx * bx, by2 = by * by;
  const S bz1_sq = bz1 * bz1;
  const S p = (bz2 * bz2 + bx2 - by2) / (S(2) * bz2);
  SVector<S> out{
      Vec3<S>(std::atan2(S(2) * bx * bz1, bz1_sq + by2 - bx2),
              std::atan2(S(2) * by * bz1, bz1_sq + bx2 - by2), S(0.5) * std::log(p * p + by2)),
      DecodeStatus::kOk};
  // Unreachable with |B| <= 1 T and film constants of sane size; guards absurd constants.
  if (!AllFinite(out.s)) return flagged(DecodeStatus::kOutOfRange);
  return out;
}

// S of a reading straight from the chip (or through CompensateReading): a saturated axis is a
// bound, not a measurement, so nothing is decoded from it.
template <typename S>
SVector<S> ComputeS(const FilmConstants<S>& film, const FieldReading<S>& reading) {
  if (!reading.valid) return {Vec3<S>::Zero(), DecodeStatus::kNonFiniteInput};
  if (reading.saturated) return {Vec3<S>::Zero(), DecodeStatus::kSaturated};
  return ComputeS<S>(film, reading.field_t);
}

// f = a ⊙ S + b, from the F/T jig (a) and no-load averaging (b).
template <typename S>
struct ForceCalibration {
  Vec3<S> a;  // N per unit of S, per axis
  Vec3<S> b;  // N
};

template <typename S>
struct ForceResult {
  Vec3<S> force_n;  // sensor frame; zero unless status is kOk
  DecodeStatus status;
  bool ok() const { return status == DecodeStatus::kOk; }
};

template <typename S>
ForceResult<S> ForceFromS(const ForceCalibration<S>& calibration, const SVector<S>& s) {
  if (!s.ok()) return {Vec3<S>::Zero(), s.status};
  if (!AllFinite(calibration.a) || !AllFinite(calibration.b)) {
    return {Vec3<S>::Zero(), DecodeStatus::kNonFiniteInput};
  }
  const Vec3<S> force_n = calibration.a.cwiseProduct(s.s) + calibration.b;
  if (!AllFinite(force_n)) return {Vec3<S>::Zero(), DecodeStatus::kOutOfRange};
  return {force_n, DecodeStatus::kOk};
}

template <typename S>
ForceResult<S> DecodeForce(const FilmConstants<S>& film, const ForceCalibration<S>& calibration,
                           const NoDeduce<Vec3<S>>& compensated_field_t) {
  return ForceFromS<S>(calibration, ComputeS<S>(film, compensated_field_t));
}

template <typename S>
ForceResult<S> DecodeForce(const FilmConstants<S>& film, const ForceCalibration<S>& calibration,
                           const FieldReading<S>& compensated_reading) {
  return ForceFromS<S>(calibration, ComputeS<S>(film, compensated_reading));
}

}  // namespace hilrig::dut_fw
