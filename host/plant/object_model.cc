#include "host/plant/object_model.h"

#include <cmath>

namespace hilrig::host {
namespace {

rig::Result<void> FieldError(const ObjectParams& object, const char* field, const char* problem) {
  return rig::MakeError("object '" + object.name + "': " + field + ": " + problem);
}

bool PositiveFinite(double value) { return std::isfinite(value) && value > 0; }
// A limit may be infinite (never reached) but must be positive.
bool PositiveLimit(double value) { return !std::isnan(value) && value > 0; }

// (d / L)^2, 0 when the law does not stiffen (L = inf).
double StiffeningTerm(const ObjectParams& object, double indentation_m) {
  const double ratio = indentation_m / object.stiffening_length_m;
  return ratio * ratio;
}

}  // namespace

const char* DamageModeName(DamageMode mode) {
  switch (mode) {
    case DamageMode::kNone:
      return "none";
    case DamageMode::kBurst:
      return "burst";
    case DamageMode::kCrack:
      return "crack";
    case DamageMode::kShatter:
      return "shatter";
    case DamageMode::kCrush:
      return "crush";
  }
  return "unknown";
}

rig::Result<void> ValidateObject(const ObjectParams& object) {
  if (!PositiveFinite(object.mass_kg))
    return FieldError(object, "mass_kg", "must be finite and > 0");
  if (!PositiveFinite(object.half_width_m)) {
    return FieldError(object, "half_width_m", "must be finite and > 0");
  }
  if (!PositiveFinite(object.half_height_m)) {
    return FieldError(object, "half_height_m", "must be finite and > 0");
  }
  if (!(std::isfinite(object.inertia_factor) && object.inertia_factor >= 0)) {
    return FieldError(object, "inertia_factor", "must be finite and >= 0");
  }
  if (!PositiveFinite(object.stiffness)) {
    return FieldError(object, "stiffness", "must be finite and > 0");
  }
  if (!(object.exponent >= 1.0 && object.exponent <= 3.0)) {
    return FieldError(object, "exponent", "must lie in [1, 3]");
  }
  if (!PositiveLimit(object.stiffening_length_m)) {
    return FieldError(object, "stiffening_length_m", "must be > 0 (inf for none)");
  }
  if (!(std::isfinite(object.friction_static) && object.friction_static >= 0)) {
    return FieldError(object, "friction_static", "must be finite and >= 0");
  }
  if (!(std::isfinite(object.friction_kinetic) && object.friction_kinetic >= 0 &&
        object.friction_kinetic <= object.friction_static)) {
    return FieldError(object, "friction_kinetic", "must be finite, >= 0 and <= friction_static");
  }
  if (!PositiveLimit(object.damage_force_n)) {
    return FieldError(object, "damage_force_n", "must be > 0 (inf for none)");
  }
  if (!PositiveLimit(object.damage_strain)) {
    return FieldError(object, "damage_strain", "must be > 0 (inf for none)");
  }
  return {};
}

double ObjectContactForce(const ObjectParams& object, double d) {
  double stiffness = 0.0;
  return ObjectContactForceAndStiffness(object, d, &stiffness);
}

double ObjectContactStiffness(const ObjectParams& object, double d) {
  double stiffness = 0.0;
  ObjectContactForceAndStiffness(object, d, &stiffness);
  return stiffness;
}

double ObjectContactEnergy(const ObjectParams& object, double d) {
  if (!(d > 0)) return 0.0;
  const double n = object.exponent;
  const double power = PowerOfIndentation(d, n);
  return object.stiffness * power * d * (1.0 / (n + 1.0) + StiffeningTerm(object, d) / (n + 3.0));
}

bool DamageReached(const ObjectParams& object, double normal_force_n, double indentation_m) {
  if (object.damage_mode == DamageMode::kNone) return false;
  if (std::isfinite(normal_force_n) && normal_force_n >= object.damage_force_n) return true;
  return std::isfinite(indentation_m) && object.half_width_m > 0 &&
         indentation_m / object.half_width_m >= object.damage_strain;
}

ObjectParams WithStiffnessScale(ObjectParams object, double factor) {
  object.stiffness *= factor;
  return object;
}

}  // namespace hilrig::host
