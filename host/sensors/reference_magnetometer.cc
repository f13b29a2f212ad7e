#include "host/sensors/reference_magnetometer.h"

#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

inline std::int16_t QuantizeAxis(double field_t, double lsb_t, bool& saturated) {
  constexpr double kMin = std::numeric_limits<std::int16_t>::min();
  constexpr double kMax = std::numeric_limits<std::int16_t>::max();
  const double counts = std::round(field_t / lsb_t);
  if (!(counts >= kMin)) {  // also catches NaN
    saturated = true;
    return counts > 0 ? static_cast<std::int16_t>(kMax) : static_cast<std::int16_t>(kMin);
  }
  if (counts > kMax) {
    saturated = true;
    return static_cast<std::int16_t>(kMax);
  }
  return static_cast<std::int16_t>(counts);
}

}  // namespace

Mlx90393Codes QuantizeMlx90393(const Eigen::Vector3d& field_sensor_t, double lsb_xy_t,
                               double lsb_z_t) {
  Mlx90393Codes out;
  out.code[0] = QuantizeAxis(field_sensor_t.x(), lsb_xy_t, out.saturated);
  out.code[1] = QuantizeAxis(field_sensor_t.y(), lsb_xy_t, out.saturated);
  out.code[2] = QuantizeAxis(field_sensor_t.z(), lsb_z_t, out.saturated);
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
  // (R_WB R_BS)^T B_world = R_SB R_WB^T B_world.
  reading.field_sensor_t =
      (orientation_world_body * params.mounting).conjugate() * earth.field_world_t;
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
