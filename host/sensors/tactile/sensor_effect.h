// The effects of the tactile forward model that a scene can switch off (models.tactile), as one
// typed list: the force-error budget (fixtures/calibration/accuracy_budget.h) measures what each
// costs in held-out accuracy, and the work-precision sweep (host/work_precision/) what leaving
// each out of a scene costs in error and gains in time. Each effect's name is its switch's field
// name in proto/scenario.proto's Tactile message.
#pragma once

#include <array>
#include <cstddef>

namespace hilrig::host {

enum class SensorEffect {
  kChipNoise,
  kEarthField,
  kSiliconeDamping,
  kSiliconeStiffening,
  kChipSaturation,
  kChipEncoding,
};

inline constexpr std::array<SensorEffect, 6> kSensorEffects = {
    SensorEffect::kChipNoise,       SensorEffect::kEarthField,
    SensorEffect::kSiliconeDamping, SensorEffect::kSiliconeStiffening,
    SensorEffect::kChipSaturation,  SensorEffect::kChipEncoding};

// "chip_noise", "earth_field", "silicone_damping", "silicone_stiffening", "chip_saturation",
// "chip_encoding": the models.tactile field that switches it. Cannot fail.
const char* SensorEffectName(SensorEffect effect);

// Which effects are on, indexed like kSensorEffects.
using EffectSet = std::array<bool, kSensorEffects.size()>;

// The full model: what a scene has unless it switches an effect (silicone stiffening is off by
// default).
inline constexpr EffectSet kDefaultEffects = {true, true, true, false, true, true};

// Whether `effect` is on unless a scene switches it.
constexpr bool OnByDefault(SensorEffect effect) {
  for (std::size_t i = 0; i < kSensorEffects.size(); ++i) {
    if (kSensorEffects[i] == effect) return kDefaultEffects[i];
  }
  return false;
}

}  // namespace hilrig::host
