#include "host/sensors/imu_emulator.h"

#include <array>
#include <cmath>

namespace hilrig::host {
namespace {

Eigen::Vector3d GaussianVector(RandomStream& rng, double sigma) {
  return sigma * StandardGaussianVector(rng);
}

}  // namespace

ImuState MakeImuState(const ImuParams& params, RandomStream rng) {
  ImuState state;
  state.rng = rng;
  if (params.noise_enabled) {
    state.gyro_bias_rad_s = GaussianVector(state.rng, params.gyro_bias_sigma_rad_s);
    state.accel_bias_m_s2 = GaussianVector(state.rng, params.accel_bias_sigma_m_s2);
  }
  return state;
}

ImuNoiseScales MakeImuNoiseScales(const ImuParams& params) {
  const double sqrt_rate = std::sqrt(params.rate_hz);
  return {params.gyro_noise_density_rad_s_sqrt_hz * sqrt_rate,
          params.accel_noise_density_m_s2_sqrt_hz * sqrt_rate,
          params.gyro_bias_random_walk_rad_s2_sqrt_hz / sqrt_rate,
          params.accel_bias_random_walk_m_s3_sqrt_hz / sqrt_rate};
}

ImuReading SampleImu(const ImuParams& params, ImuState& state,
                     const Eigen::Vector3d& angular_velocity_body_rad_s,
                     const Eigen::Vector3d& specific_force_body_m_s2, std::int64_t time_ns) {
  return SampleImu(params, MakeImuNoiseScales(params), state, angular_velocity_body_rad_s,
                   specific_force_body_m_s2, time_ns);
}

namespace {

// Each axis of `value` held within ±range; true when one was outside it (a value that is no
// number passes through: the run stops on it elsewhere).
bool Clip(Eigen::Vector3d& value, double range) {
  bool clipped = false;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(value[axis]) > range) {
      value[axis] = std::copysign(range, value[axis]);
      clipped = true;
    }
  }
  return clipped;
}

ImuReading Saturated(const ImuParams& params, ImuReading reading) {
  reading.gyro_clipped = Clip(reading.gyro_rad_s, params.gyro_range_rad_s);
  reading.accel_clipped = Clip(reading.accel_m_s2, params.accel_range_m_s2);
  return reading;
}

}  // namespace

ImuReading SampleImu(const ImuParams& params, const ImuNoiseScales& scales, ImuState& state,
                     const Eigen::Vector3d& angular_velocity_body_rad_s,
                     const Eigen::Vector3d& specific_force_body_m_s2, std::int64_t time_ns) {
  ImuReading reading;
  reading.time_ns = time_ns;
  if (!params.noise_enabled) {
    reading.gyro_rad_s = angular_velocity_body_rad_s;
    reading.accel_m_s2 = specific_force_body_m_s2;
    return Saturated(params, reading);
  }
  // Draw order is fixed (gyro noise, accel noise, gyro walk, accel walk, x y z each): it is part
  // of the stream's reproducibility. One batch keeps the generator in registers for all twelve.
  std::array<double, 12> draws;
  FillStandardGaussians(state.rng, draws);
  const auto axes = [&draws](int first) {
    return Eigen::Vector3d(draws[first], draws[first + 1], draws[first + 2]);
  };
  reading.gyro_rad_s =
      angular_velocity_body_rad_s + state.gyro_bias_rad_s + scales.gyro_noise_rad_s * axes(0);
  reading.accel_m_s2 =
      specific_force_body_m_s2 + state.accel_bias_m_s2 + scales.accel_noise_m_s2 * axes(3);
  state.gyro_bias_rad_s += scales.gyro_walk_rad_s * axes(6);
  state.accel_bias_m_s2 += scales.accel_walk_m_s2 * axes(9);
  return Saturated(params, reading);
}

}  // namespace hilrig::host
