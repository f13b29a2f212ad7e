#include "host/sensors/tactile/mlx90393_model.h"

#include <cmath>

#include "rig/check.h"

namespace hilrig::host {
namespace {

// std::round (half away from zero) without the libm call it compiles to on baseline x86-64: the
// truncation through int64 and the fraction v - trunc(v) are exact below 2^52, and every larger
// double (and NaN or Inf) is returned as std::round returns it. The one difference, -0.0 for
// small negative v where this gives +0.0, is invisible once converted to counts.
double RoundHalfAwayFromZero(double v) {
  if (!(std::fabs(v) < 0x1.0p52)) return v;
  const double truncated = static_cast<double>(static_cast<std::int64_t>(v));
  const double fraction = v - truncated;
  if (fraction >= 0.5) return truncated + 1.0;
  if (fraction <= -0.5) return truncated - 1.0;
  return truncated;
}

}  // namespace

Mlx90393AxisCounts QuantizeMlx90393Axis(double field_t, double lsb_t, std::int32_t min_counts,
                                        std::int32_t max_counts) {
  const double counts = RoundHalfAwayFromZero(field_t / lsb_t);
  if (!(counts >= min_counts)) {  // also catches NaN
    return {counts > 0 ? max_counts : min_counts, true};
  }
  if (counts > max_counts) return {max_counts, true};
  return {static_cast<std::int32_t>(counts), false};
}

Mlx90393Constants MakeMlx90393Constants(const Mlx90393Params& params) {
  HILRIG_CHECK(dut_fw::IsValidSetting(params.setting), "MLX90393 GAIN_SEL 0..7, RES 0..3");
  return {.lsb_t = dut_fw::LsbTesla<double>(params.setting),
          .range = dut_fw::CodeRange(params.setting.resolution),
          .noise_sigma_t = Eigen::Vector3d(params.noise_xy_t, params.noise_xy_t, params.noise_z_t)};
}

Mlx90393Sample SampleMlx90393(const Mlx90393Params& params, Mlx90393State& state,
                              const Eigen::Vector3d& field_sensor_t, double temperature_c) {
  return SampleMlx90393(params, MakeMlx90393Constants(params), state, field_sensor_t,
                        temperature_c);
}

Mlx90393Sample SampleMlx90393(const Mlx90393Params& params, const Mlx90393Constants& constants,
                              Mlx90393State& state, const Eigen::Vector3d& field_sensor_t,
                              double temperature_c) {
  Mlx90393Sample sample;

  Eigen::Vector3d sensed = field_sensor_t;
  if (params.drift_enabled) {
    const double dt_k = temperature_c - params.reference_temperature_c;
    sensed = (1.0 + params.sensitivity_tempco_per_k * dt_k) * sensed +
             params.offset_at_reference_t + params.offset_tempco_t_per_k * dt_k;
  }
  if (params.noise_enabled) {
    // Always three draws in axis order, so the stream stays aligned across configurations.
    sensed += constants.noise_sigma_t.cwiseProduct(StandardGaussianVector(state.rng));
  }

  const dut_fw::Mlx90393CodeRange& range = constants.range;
  const Eigen::Vector3d& lsb_t = constants.lsb_t;
  for (int axis = 0; axis < 3; ++axis) {
    if (params.saturation_enabled && params.encoding_enabled) {
      // The chip as specified: dut_fw's encoder clips and encodes.
      constexpr std::int32_t kWide = 1 << 30;
      const Mlx90393AxisCounts q = QuantizeMlx90393Axis(sensed[axis], lsb_t[axis], -kWide, kWide);
      const dut_fw::EncodedCode encoded = dut_fw::EncodeCode(q.counts, range);
      sample.code[axis] = encoded.code;
      sample.saturated = sample.saturated || q.clipped || encoded.saturated;
      continue;
    }
    // A switched-off effect: clip or not, offset or not, then keep the register's low 16 bits
    // (the cast to an unsigned type is defined modulo 2^16).
    const std::int32_t lo = params.saturation_enabled ? range.min_counts : -(1 << 30);
    const std::int32_t hi = params.saturation_enabled ? range.max_counts : (1 << 30);
    const Mlx90393AxisCounts q = QuantizeMlx90393Axis(sensed[axis], lsb_t[axis], lo, hi);
    const std::int32_t zero_code = params.encoding_enabled ? range.zero_code : 0;
    sample.code[axis] = static_cast<std::uint16_t>(q.counts + zero_code);
    sample.saturated = sample.saturated || q.clipped || dut_fw::CountsSaturated(q.counts, range);
  }
  return sample;
}

}  // namespace hilrig::host
