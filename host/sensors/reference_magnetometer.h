// The unloaded reference Hall sensor (an MLX90393 on the body, away from any magnet): it reads
// Earth's field rotated into the sensor frame by the vehicle attitude, which lets the DUT
// subtract the Earth-field part from the tactile sensors' readings. Emulated effects: Gaussian
// noise per axis, quantization to the per-axis LSB at the highest gain, int16 saturation (flagged)
// and a fixed sample rate. The encoding of the codes on the wire (RES-dependent offsets) belongs
// to the device emulator, not here.
//
// World frame for the Earth field: x east, y north, z up (ENU), matching the rig's world z up.
// The default is ~48 µT with 60° inclination (24 µT north, 41.6 µT down), mid-latitude Europe.
#ifndef HILRIG_HOST_SENSORS_REFERENCE_MAGNETOMETER_H_
#define HILRIG_HOST_SENSORS_REFERENCE_MAGNETOMETER_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>

#include "host/sensors/random_stream.h"

namespace hilrig::host {

struct EarthField {
  Eigen::Vector3d field_world_t = {0.0, 2.4e-5, -4.16e-5};
};

struct MagnetometerParams {
  double rate_hz = 50.0;
  Eigen::Quaterniond mounting = Eigen::Quaterniond::Identity();  // sensor -> body (R_BS)
  double lsb_xy_t = 0.150e-6;
  double lsb_z_t = 0.242e-6;
  double noise_t = 0.3e-6;  // per axis, 1 sigma
  bool noise_enabled = true;
  std::uint8_t node_id = 7;
};

struct MagnetometerState {
  RandomStream rng;
  std::int64_t next_sample_ns = 0;
  std::uint8_t sequence = 0;  // wraps, as the 8-bit counter on the wire does
};

struct MagnetometerReading {
  std::int64_t time_ns = 0;
  std::uint8_t node_id = 0;
  Eigen::Vector3d field_sensor_t = Eigen::Vector3d::Zero();  // noisy, before quantization
  std::array<std::int16_t, 3> code{};                        // round(field / lsb), saturated
  bool saturated = false;                                    // any axis clipped to int16
  std::uint8_t sequence = 0;
};

// Earth's field in a sensor's frame: R_SB R_WB^T B_world = (R_WB R_BS)^T B_world. The one copy
// of this rotation, shared by the reference magnetometer and the tactile sensors, so that the
// geomagnetic compensation on the DUT is tested against a single convention.
Eigen::Vector3d EarthFieldInSensorFrame(const Eigen::Quaterniond& orientation_world_body,
                                        const Eigen::Quaterniond& mounting_body_sensor,
                                        const Eigen::Vector3d& field_world_t);

// One axis of MLX90393 quantization: field / lsb rounded half away from zero, clipped to
// [min_counts, max_counts]; `clipped` is set when it had to be clipped or was not finite (a NaN
// goes to min_counts). The tactile chip model (tactile/mlx90393_model.h) rounds with it too.
struct Mlx90393AxisCounts {
  std::int32_t counts = 0;
  bool clipped = false;
};
Mlx90393AxisCounts QuantizeMlx90393Axis(double field_t, double lsb_t, std::int32_t min_counts,
                                        std::int32_t max_counts);

// MLX90393 quantization shared with the tactile emulators: rounds half away from zero and
// clips to int16; `saturated` tells whether any axis was clipped (or was not finite).
struct Mlx90393Codes {
  std::array<std::int16_t, 3> code{};
  bool saturated = false;
};
Mlx90393Codes QuantizeMlx90393(const Eigen::Vector3d& field_sensor_t, double lsb_xy_t,
                               double lsb_z_t);

std::int64_t MagnetometerPeriodNs(const MagnetometerParams& params);

// Field in the sensor frame = R_SB * R_WB^T * B_world + noise, quantized. Returns a reading when
// now >= next_sample (then schedules the next one a period after the previous scheduled time,
// skipping any periods the caller jumped over), else nullopt.
std::optional<MagnetometerReading> SampleReferenceMagnetometer(
    const MagnetometerParams& params, const EarthField& earth, MagnetometerState& state,
    const Eigen::Quaterniond& orientation_world_body, std::int64_t now_ns);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_REFERENCE_MAGNETOMETER_H_
