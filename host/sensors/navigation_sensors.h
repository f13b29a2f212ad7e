// The navigation sensors a flight stack fuses besides the IMU and VIO, as measurement models:
// a magnetometer, a barometer and a GNSS receiver (the devices that schedule them are
// host/runner/navigation_devices.h). With R_WB the vehicle's attitude and p its world position
// (x east, y north, z up) relative to the geodetic `origin`:
//
//   magnetometer  m = R_WB^T B_earth + b_stray + n_m,              n_m ~ N(0, noise_t^2 I), FLU, T
//   barometer     P = P_isa(h_origin + p_z) + n_P,                  n_P ~ N(0, noise_pa^2), Pa
//                 T = T_isa(h_origin + p_z)                          (no noise), °C
//   GNSS          (lat, lon) = origin + (p_y + n_n, p_x + n_e) over the WGS-84 radii at the origin
//                 alt = h_origin + p_z + n_u,  v = v_world + n_v   n ~ N(0, σ^2) per axis
//
// P_isa and T_isa are the International Standard Atmosphere's troposphere (rig/
// standard_atmosphere.h). Every
// noise draws from the sensor's own random stream; with noise disabled a model draws nothing.
#ifndef HILRIG_HOST_SENSORS_NAVIGATION_SENSORS_H_
#define HILRIG_HOST_SENSORS_NAVIGATION_SENSORS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "host/sensors/random_stream.h"

namespace hilrig::host {

// A point on WGS-84: degrees, and metres above mean sea level.
struct GeodeticPoint {
  double latitude_deg = 0;
  double longitude_deg = 0;
  double altitude_m = 0;
};

// Zürich (47.3769 N, 8.5417 E, 408 m): Earth's field there (about 48 µT, 63° down, 3° east of
// north) is within a flight stack's tolerance of the rig's default Earth field (host/sensors/
// earth_field.h: 48 µT, 60° down, due north).
inline constexpr GeodeticPoint kDefaultGeodeticOrigin{47.3769, 8.5417, 408.0};

struct MagnetometerParams {
  double rate_hz = 100.0;
  double noise_t = 1e-7;  // 1 mG per axis
  // The vehicle's own field at the magnetometer (motors, battery), constant in the body frame.
  Eigen::Vector3d stray_field_body_t = Eigen::Vector3d::Zero();
  bool noise_enabled = true;
};

struct BarometerParams {
  double rate_hz = 50.0;
  double noise_pa = 1.5;  // about 0.13 m of altitude near sea level
  bool noise_enabled = true;
};

struct GnssParams {
  double rate_hz = 10.0;
  double horizontal_noise_m = 0.3;
  double vertical_noise_m = 0.5;
  double velocity_noise_m_s = 0.05;
  int satellites = 12;
  bool noise_enabled = true;
};

struct NavigationSensorsConfig {
  GeodeticPoint origin = kDefaultGeodeticOrigin;
  MagnetometerParams magnetometer;
  BarometerParams barometer;
  GnssParams gnss;
};

// The point `local_m` (x east, y north, z up) away from `origin`, on the tangent plane at the
// origin with WGS-84's meridian and prime-vertical radii there: millimetre-exact over the few
// hundred metres a scene spans. Cannot fail; O(1).
GeodeticPoint GeodeticFromLocal(const GeodeticPoint& origin, const Eigen::Vector3d& local_m);

// One magnetometer reading, FLU body frame, tesla (see the formula above).
Eigen::Vector3d SampleMagnetometer(const MagnetometerParams& params,
                                   const Eigen::Quaterniond& orientation_world_body,
                                   const Eigen::Vector3d& earth_field_world_t, RandomStream& rng);

struct BarometerReading {
  double pressure_pa = 0;
  double temperature_c = 0;
};
BarometerReading SampleBarometer(const BarometerParams& params, double altitude_m,
                                 RandomStream& rng);

struct GnssReading {
  GeodeticPoint position;
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();  // east, north, up
  double horizontal_accuracy_m = 0;  // the model's one-sigma (0.01 m with noise disabled)
  double vertical_accuracy_m = 0;
};
GnssReading SampleGnss(const GnssParams& params, const GeodeticPoint& origin,
                       const Eigen::Vector3d& position_m, const Eigen::Vector3d& velocity_m_s,
                       RandomStream& rng);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_NAVIGATION_SENSORS_H_
