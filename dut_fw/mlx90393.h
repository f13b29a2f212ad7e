// Datasheet facts of the MLX90393 Hall chip that turn its 16-bit output codes into tesla: the
// sensitivity (LSB size) per GAIN_SEL and RES, the RES-dependent output encoding, and the rails
// that mark a saturated axis. The sensor-node firmware and the DUT decode with these; the host's
// device emulator encodes with EncodeCode, so both sides share one statement of the chip's output
// format instead of two that could drift apart.
//
// Scope: HALLCONF = 0xC (the power-on default and the only setting the rig uses), temperature
// compensation off (TCMP_EN = 0; with it on every RES is offset-binary around 32768, which this
// header does not model), one RES for all three axes (the chip allows RES_X/Y/Z separately; the
// tactile nodes never use that).
//
// Encoding per RES (datasheet, as implemented by the Adafruit and tedyapo drivers):
//   RES 0, 1: two's complement int16, full int16 range.
//   RES 2:    unsigned, zero field at 32768, output range ±22000 LSB around it.
//   RES 3:    unsigned, zero field at 16384, output range ±11000 LSB around it.
// RES 2 and 3 drop low bits of the same 19-bit ADC instead of clipping to int16, hence the narrower
// code ranges: both span ±88000 RES-0 LSBs, while RES 0 and 1 hit the int16 rails first.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

struct Mlx90393Setting {
  std::uint8_t gain_sel;    // GAIN_SEL, 0 (5x, least sensitive) .. 7 (1x, most sensitive)
  std::uint8_t resolution;  // RES_XYZ, 0..3; each step doubles the LSB
};

inline constexpr std::uint8_t kMlx90393MaxGainSel = 7;
inline constexpr std::uint8_t kMlx90393MaxResolution = 3;

constexpr bool IsValidSetting(Mlx90393Setting setting) {
  return setting.gain_sel <= kMlx90393MaxGainSel && setting.resolution <= kMlx90393MaxResolution;
}

namespace mlx90393_internal {

// RES 0 column of the datasheet's sensitivity table for HALLCONF 0xC, µT/LSB, {x/y, z}, indexed by
// GAIN_SEL. Higher RES values are these times 2^RES, exactly, since RES only selects which bits of
// the same ADC word are output. The printed RES 1..3 columns agree with that to within the rounding
// of the three-decimal RES 0 entries (<= 0.25 %), except GAIN_SEL 1 / RES 3 x/y, printed 4.840
// where every neighbour says 4.81 -- a misprint, and the reason the table is not copied as printed.
inline constexpr double kRes0LsbMicroTesla[8][2] = {
    {0.751, 1.210},  // GAIN_SEL 0, 5x
    {0.601, 0.968},  // 1, 4x
    {0.451, 0.726},  // 2, 3x
    {0.376, 0.605},  // 3, 2.5x
    {0.300, 0.484},  // 4, 2x
    {0.250, 0.403},  // 5, 1.667x
    {0.200, 0.323},  // 6, 1.333x
    {0.150, 0.242},  // 7, 1x
};

// Every setting's LSB in tesla, {x/y, z}, worked out in double and rounded to S when the firmware
// is compiled: the firmware reads a table of S, so a float build does no double arithmetic per
// sample (the target has a single-precision FPU only).
template <typename S>
constexpr std::array<std::array<std::array<S, 2>, 4>, 8> MakeLsbTeslaTable() {
  std::array<std::array<std::array<S, 2>, 4>, 8> table{};
  for (std::size_t gain = 0; gain < table.size(); ++gain) {
    for (std::size_t resolution = 0; resolution < table[gain].size(); ++resolution) {
      const double scale = 1e-6 * double(1u << resolution);
      table[gain][resolution] = {S(kRes0LsbMicroTesla[gain][0] * scale),
                                 S(kRes0LsbMicroTesla[gain][1] * scale)};
    }
  }
  return table;
}
template <typename S>
inline constexpr auto kLsbTesla = MakeLsbTeslaTable<S>();

}  // namespace mlx90393_internal

// LSB size in tesla per axis (x, y, z). An invalid setting yields NaN on every axis so a misuse
// poisons whatever it touches instead of passing for a plausible sensitivity.
template <typename S>
Vec3<S> LsbTesla(Mlx90393Setting setting) {
  if (!IsValidSetting(setting)) return Vec3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
  const auto& lsb = mlx90393_internal::kLsbTesla<S>[setting.gain_sel][setting.resolution];
  return Vec3<S>(lsb[0], lsb[0], lsb[1]);
}

// The zero-field code and the symmetric output limits (in counts, i.e. LSBs from zero field) of a
// RES setting. RES 0/1 are asymmetric like any int16: [-32768, 32767].
struct Mlx90393CodeRange {
  std::int32_t zero_code;   // code of zero field
  std::int32_t min_counts;  // lowest counts the chip outputs (the negative rail)
  std::int32_t max_counts;  // highest counts the chip outputs (the positive rail)
};

// `resolution` must be 0..3 (IsValidSetting); larger values are treated as 3.
constexpr Mlx90393CodeRange CodeRange(std::uint8_t resolution) {
  switch (resolution) {
    case 0:
    case 1:
      return {0, -32768, 32767};
    case 2:
      return {32768, -22000, 22000};
    default:  // 3; callers validate the setting first
      return {16384, -11000, 11000};
  }
}

// Counts (signed LSBs from zero field) of a code as the chip encodes it at `resolution`. Codes
// outside the chip's output range (which a healthy chip never produces) come back as they are, so
// the caller's rail test flags them.
constexpr std::int32_t CodeToCounts(std::uint16_t code, std::uint8_t resolution) {
  if (resolution <= 1) return std::int32_t(std::int16_t(code));
  return std::int32_t(code) - CodeRange(resolution).zero_code;
}

// True when `counts` is at or beyond a rail: the true field may be anywhere beyond it. The range
// overloads here and below are for callers that hold CodeRange(resolution) already.
constexpr bool CountsSaturated(std::int32_t counts, const Mlx90393CodeRange& range) {
  return counts <= range.min_counts || counts >= range.max_counts;
}
constexpr bool CountsSaturated(std::int32_t counts, std::uint8_t resolution) {
  return CountsSaturated(counts, CodeRange(resolution));
}

struct EncodedCode {
  std::uint16_t code;
  bool saturated;  // clipped to a rail, or landed exactly on one (indistinguishable to a reader)
};

// The chip's output stage: clip `counts` to the output range of `resolution` and encode. This is
// the format on the wire, not a decoder; the host's device emulator uses it after quantizing the
// field, so the DUT decodes exactly what a real chip would have sent.
constexpr EncodedCode EncodeCode(std::int32_t counts, const Mlx90393CodeRange& range) {
  const std::int32_t clipped = counts < range.min_counts
                                   ? range.min_counts
                                   : (counts > range.max_counts ? range.max_counts : counts);
  const std::int32_t code = clipped + range.zero_code;  // RES 0/1: two's complement below
  return {std::uint16_t(code & 0xFFFF), CountsSaturated(clipped, range)};
}
constexpr EncodedCode EncodeCode(std::int32_t counts, std::uint8_t resolution) {
  return EncodeCode(counts, CodeRange(resolution));
}

// One X/Y/Z measurement as read from the chip; decode with CodesToTesla(setting, raw.code).
struct RawReading {
  std::array<std::uint16_t, 3> code;  // x, y, z
};

template <typename S>
struct FieldReading {
  Vec3<S> field_t;  // NaN on every axis when !valid
  bool saturated;   // at least one axis at a rail: that axis is a bound, not a measurement
  bool valid;       // the setting was a real one
};

template <typename S>
FieldReading<S> CodesToTesla(Mlx90393Setting setting, const std::array<std::uint16_t, 3>& codes) {
  FieldReading<S> reading;
  reading.valid = IsValidSetting(setting);
  reading.saturated = false;
  reading.field_t = LsbTesla<S>(setting);
  if (!reading.valid) return reading;
  const Mlx90393CodeRange range = CodeRange(setting.resolution);
  for (int axis = 0; axis < 3; ++axis) {
    const std::int32_t counts = CodeToCounts(codes[axis], setting.resolution);
    reading.saturated = reading.saturated || CountsSaturated(counts, range);
    reading.field_t[axis] *= S(counts);
  }
  return reading;
}

}  // namespace hilrig::dut_fw
