// The IMU emulator: turns the plant's body rates and specific force into gyro and accelerometer
// readings with the usual discrete-time noise model: white noise of standard deviation
// density * sqrt(rate) per sample, plus a bias drawn once at power-up (turn-on bias) that then
// random-walks by walk_density / sqrt(rate) per sample. Each axis then saturates at its full
// scale, as the sensor's ADC does (±16 g and ±2000 °/s by default), and the reading says which of
// the two clipped. The IMU device (host/runner/imu_device.h)
// keeps the schedule and calls SampleImu once per IMU period; time_ns is stamped on the reading
// unchanged.
#ifndef HILRIG_HOST_SENSORS_IMU_EMULATOR_H_
#define HILRIG_HOST_SENSORS_IMU_EMULATOR_H_

#include <Eigen/Core>
#include <cstdint>

#include "host/sensors/random_stream.h"

namespace hilrig::host {

struct ImuParams {
  double rate_hz = 1000.0;
  double gyro_noise_density_rad_s_sqrt_hz = 1.7e-4;  // ~0.01 deg/s/sqrt(Hz)
  double gyro_bias_sigma_rad_s = 0.005;
  double gyro_bias_random_walk_rad_s2_sqrt_hz = 1e-5;
  double accel_noise_density_m_s2_sqrt_hz = 2e-3;
  double accel_bias_sigma_m_s2 = 0.05;
  double accel_bias_random_walk_m_s3_sqrt_hz = 1e-4;
  // Full scale per axis: ±16 g and ±2000 °/s, an MEMS IMU's widest ranges.
  double accel_range_m_s2 = 16 * 9.80665;
  double gyro_range_rad_s = 2000 * 0.017453292519943295;
  bool noise_enabled = true;
};

struct ImuState {
  RandomStream rng;
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();
};

// Draws the turn-on biases (zero, and no draws, when noise is disabled).
ImuState MakeImuState(const ImuParams& params, RandomStream rng);

struct ImuReading {
  std::int64_t time_ns = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
  bool gyro_clipped = false;  // an axis at its full scale
  bool accel_clipped = false;
};

// The standard deviations per sample that the params fix: the white noises' density * sqrt(rate)
// and the walks' density / sqrt(rate). A device computes them once instead of per sample.
struct ImuNoiseScales {
  double gyro_noise_rad_s = 0;
  double accel_noise_m_s2 = 0;
  double gyro_walk_rad_s = 0;
  double accel_walk_m_s2 = 0;
};
ImuNoiseScales MakeImuNoiseScales(const ImuParams& params);

// reading = clip(truth + bias + white noise); the biases then take one random-walk step.
ImuReading SampleImu(const ImuParams& params, ImuState& state,
                     const Eigen::Vector3d& angular_velocity_body_rad_s,
                     const Eigen::Vector3d& specific_force_body_m_s2, std::int64_t time_ns);
// The same with the scales made once by MakeImuNoiseScales(params): the same reading.
ImuReading SampleImu(const ImuParams& params, const ImuNoiseScales& scales, ImuState& state,
                     const Eigen::Vector3d& angular_velocity_body_rad_s,
                     const Eigen::Vector3d& specific_force_body_m_s2, std::int64_t time_ns);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_IMU_EMULATOR_H_
