#include "rig/standard_atmosphere.h"

#include <cmath>

namespace hilrig::rig {
namespace {

constexpr double kSeaLevelPressurePa = 101325.0;
constexpr double kSeaLevelTemperatureK = 288.15;
constexpr double kLapseRateKPerM = 0.0065;
constexpr double kKelvinOffset = 273.15;
// g0 M / (R L) = 9.80665 * 0.0289644 / (8.3144598 * 0.0065).
constexpr double kPressureExponent = 5.25588;

}  // namespace

double StandardPressurePa(double altitude_m) {
  const double temperature_ratio = 1.0 - kLapseRateKPerM * altitude_m / kSeaLevelTemperatureK;
  return kSeaLevelPressurePa * std::pow(temperature_ratio, kPressureExponent);
}

double StandardTemperatureC(double altitude_m) {
  return kSeaLevelTemperatureK - kLapseRateKPerM * altitude_m - kKelvinOffset;
}

double StandardAltitudeM(double pressure_pa) {
  const double ratio = std::pow(pressure_pa / kSeaLevelPressurePa, 1.0 / kPressureExponent);
  return (1.0 - ratio) * kSeaLevelTemperatureK / kLapseRateKPerM;
}

}  // namespace hilrig::rig
