#include "host/sensors/tactile/sensor_effect.h"

namespace hilrig::host {

const char* SensorEffectName(SensorEffect effect) {
  switch (effect) {
    case SensorEffect::kChipNoise:
      return "chip_noise";
    case SensorEffect::kEarthField:
      return "earth_field";
    case SensorEffect::kSiliconeDamping:
      return "silicone_damping";
    case SensorEffect::kSiliconeStiffening:
      return "silicone_stiffening";
    case SensorEffect::kChipSaturation:
      return "chip_saturation";
    case SensorEffect::kChipEncoding:
      return "chip_encoding";
  }
  return "unknown";
}

}  // namespace hilrig::host
