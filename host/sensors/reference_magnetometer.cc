#include "host/sensors/reference_magnetometer.h"

#include <cmath>
#include <limits>

namespace hilrig::host {
Eigen::Vector3d EarthFieldInSensorFrame(const Eigen::Quaterniond& orientation_world_body,
                                        const Eigen::Quaterniond& mounting_body_sensor,
                                        const Eigen::Vector3d& field_world_t) {
  return (orientation_world_body * mounting_body_sensor).conjugate() * field_world_t;
}

Mlx90393AxisCounts QuantizeMlx90393Axis(double field_t, double lsb_t, std::int32_t min_counts,
                                        std::int32_t max_counts) {
  const double counts = std::round(field_t / lsb_t);
  if (!(counts >= min_counts)) {  // also catches NaN
    return {counts > 0 ? max_counts : min_counts, true};
  }
  if (counts > max_counts) return {max_counts, true};
  return {static_cast<std::int32_t>(counts), false};
}

Mlx90393Codes QuantizeMlx90393(const Eigen::Vector3d& field_sensor_t, double lsb_xy_t,
                               double lsb_z_t) {
  constexpr std::int32_t kMin = std::numeric_limits<std::int16_t>::min();
  constexpr std::int32_t kMax = std::numeric_limits<std::int16_t>::max();
  const double lsb_t[3] = {lsb_xy_t, lsb_xy_t, lsb_z_t};
  Mlx90393Codes out;
  for (int i = 0; i < 3; ++i) {
    const Mlx90393AxisCounts axis = QuantizeMlx90393Axis(field_sensor_t[i], lsb_t[i], kMin, kMax);
    out.code[i] = static_cast<std::int16_t>(axis.counts);
    out.saturated = out.saturated || axis.clipped;
  }
  return out;
}

std::int64_t MagnetometerPeriodNs(const MagnetometerParams& params) {
  return std::llround(1e9 / params.rate_hz);
}

std::optional<MagnetometerReading> SampleReferenceMagnetometer(
    const MagnetometerParams& params, const EarthField& earth, MagnetometerState& state,
    const Eigen::Quaterniond& orientation_world_body, std::int64_t now_ns) {
  if (now_ns < state.next_sample_ns) return std::nullopt;

  MagnetometerReading reading;
  reading.time_ns = now_ns;
  reading.node_id = params.node_id;
  reading.sequence = state.sequence++;
  reading.field_sensor_t =
      EarthFieldInSensorFrame(orientation_world_body, params.mounting, earth.field_world_t);
  if (params.noise_enabled) {
    const double x = state.rng.Gaussian();
    const double y = state.rng.Gaussian();
    const double z = state.rng.Gaussian();
    reading.field_sensor_t += params.noise_t * Eigen::Vector3d(x, y, z);
  }
  const Mlx90393Codes codes =
      QuantizeMlx90393(reading.field_sensor_t, params.lsb_xy_t, params.lsb_z_t);
  reading.code = codes.code;
  reading.saturated = codes.saturated;

  const std::int64_t period = MagnetometerPeriodNs(params);
  state.next_sample_ns += period;
  if (state.next_sample_ns <= now_ns) {
    state.next_sample_ns += ((now_ns - state.next_sample_ns) / period + 1) * period;
  }
  return reading;
}

}  // namespace hilrig::host
