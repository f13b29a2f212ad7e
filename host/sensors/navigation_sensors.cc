#include "host/sensors/navigation_sensors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "host/sensors/earth_field.h"
#include "rig/standard_atmosphere.h"

namespace hilrig::host {
namespace {

// WGS-84.
constexpr double kEquatorialRadiusM = 6378137.0;
constexpr double kEccentricitySquared = 6.69437999014e-3;
// What a receiver claims with noise disabled: a perfect fix still has an accuracy.
constexpr double kNoiselessAccuracyM = 0.01;

double Radians(double degrees) { return degrees * std::numbers::pi / 180.0; }
double Degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

}  // namespace

GeodeticPoint GeodeticFromLocal(const GeodeticPoint& origin, const Eigen::Vector3d& local_m) {
  const double latitude_rad = Radians(origin.latitude_deg);
  const double sine = std::sin(latitude_rad);
  const double w = std::sqrt(1.0 - kEccentricitySquared * sine * sine);
  const double prime_vertical_m = kEquatorialRadiusM / w;
  const double meridian_m = kEquatorialRadiusM * (1.0 - kEccentricitySquared) / (w * w * w);
  const double height_m = origin.altitude_m;
  GeodeticPoint point;
  point.latitude_deg = origin.latitude_deg + Degrees(local_m.y() / (meridian_m + height_m));
  point.longitude_deg =
      origin.longitude_deg +
      Degrees(local_m.x() / ((prime_vertical_m + height_m) * std::cos(latitude_rad)));
  point.altitude_m = origin.altitude_m + local_m.z();
  return point;
}

Eigen::Vector3d SampleMagnetometer(const MagnetometerParams& params,
                                   const Eigen::Quaterniond& orientation_world_body,
                                   const Eigen::Vector3d& earth_field_world_t, RandomStream& rng) {
  Eigen::Vector3d field_t = EarthFieldInBodyFrame(orientation_world_body, earth_field_world_t) +
                            params.stray_field_body_t;
  if (params.noise_enabled) field_t += params.noise_t * StandardGaussianVector(rng);
  return field_t;
}

BarometerReading SampleBarometer(const BarometerParams& params, double altitude_m,
                                 RandomStream& rng) {
  BarometerReading reading{rig::StandardPressurePa(altitude_m),
                           rig::StandardTemperatureC(altitude_m)};
  if (params.noise_enabled) reading.pressure_pa += params.noise_pa * rng.Gaussian();
  return reading;
}

GnssReading SampleGnss(const GnssParams& params, const GeodeticPoint& origin,
                       const Eigen::Vector3d& position_m, const Eigen::Vector3d& velocity_m_s,
                       RandomStream& rng) {
  Eigen::Vector3d position_error_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_error_m_s = Eigen::Vector3d::Zero();
  if (params.noise_enabled) {
    const Eigen::Vector3d unit_position = StandardGaussianVector(rng);
    position_error_m = {params.horizontal_noise_m * unit_position.x(),
                        params.horizontal_noise_m * unit_position.y(),
                        params.vertical_noise_m * unit_position.z()};
    velocity_error_m_s = params.velocity_noise_m_s * StandardGaussianVector(rng);
  }
  GnssReading reading;
  reading.position = GeodeticFromLocal(origin, position_m + position_error_m);
  reading.velocity_m_s = velocity_m_s + velocity_error_m_s;
  reading.horizontal_accuracy_m = params.noise_enabled
                                      ? std::max(params.horizontal_noise_m, kNoiselessAccuracyM)
                                      : kNoiselessAccuracyM;
  reading.vertical_accuracy_m = params.noise_enabled
                                    ? std::max(params.vertical_noise_m, kNoiselessAccuracyM)
                                    : kNoiselessAccuracyM;
  return reading;
}

}  // namespace hilrig::host
