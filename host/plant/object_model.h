// What a grasped object is, mechanically: its mass and size, the local contact law between one
// pad and the object's surface, friction against the pad silicone, and when it breaks. The
// contact law F = k d^n (1 + (d / L)^2) covers the fixtures with one formula: n = 1 for a shell or
// foam whose wall bends (balloon, bottle, stress ball), n = 1.5 for a rigid curved body touched
// by a flat pad (Hertz: egg, glass, wood), and the (d / L)^2 term for a body that stiffens as it
// is squeezed (membrane tension in a balloon, a foam's cells closing). Damage is a per-contact
// criterion on the normal force or on the indentation relative to the half width; what happens
// on damage (the object is gone, or stays cracked) is the contact model's business.
#ifndef HILRIG_HOST_PLANT_OBJECT_MODEL_H_
#define HILRIG_HOST_PLANT_OBJECT_MODEL_H_

#include <cmath>
#include <limits>
#include <string>

#include "rig/result.h"

namespace hilrig::host {

enum class DamageMode { kNone, kBurst, kCrack, kShatter, kCrush };
const char* DamageModeName(DamageMode mode);  // "none", "burst", "crack", "shatter", "crush"

struct ObjectParams {
  std::string name;
  double mass_kg = 0.05;
  double half_width_m = 0.03;  // centre to contact surface along each pad normal
  // Centre to top and to bottom along the pads' height (world z on the stand, body z when held):
  // the pads reach the object only within this (plus their own half height) of its centre.
  double half_height_m = 0.03;
  // Moment of inertia about any axis through the centre, as a multiple of m half_width^2: 2/5 a
  // solid ball (the default; near enough for the compact fixtures), 2/3 a thin spherical shell.
  double inertia_factor = 0.4;
  // Local contact law at each pad, indentation d >= 0 (m):
  //   F = stiffness * d^exponent * (1 + (d / stiffening_length_m)^2)
  double stiffness = 1e3;  // N / m^exponent
  double exponent = 1.0;   // 1 linear (shells, foam), 1.5 Hertz (rigid curved bodies)
  double stiffening_length_m = std::numeric_limits<double>::infinity();
  double friction_static = 0.8;  // pad silicone on the object
  double friction_kinetic = 0.6;
  DamageMode damage_mode = DamageMode::kNone;
  double damage_force_n =
      std::numeric_limits<double>::infinity();  // per-contact normal force limit
  double damage_strain =
      std::numeric_limits<double>::infinity();  // per-contact indentation / half_width
};

// Finite positive mass/size/stiffness, finite inertia factor >= 0, exponent in [1, 3],
// 0 <= kinetic <= static (finite), stiffening length and damage limits > 0 (inf allowed); the
// message names the field.
rig::Result<void> ValidateObject(const ObjectParams& object);

// The contact law; 0 for d <= 0 or a NaN indentation.
double ObjectContactForce(const ObjectParams& object, double indentation_m);
// dF/dd (>= 0); 0 for d <= 0 except for a linear law, whose slope is k from the first touch.
double ObjectContactStiffness(const ObjectParams& object, double indentation_m);
// Energy stored in one contact at indentation d: the integral of F from 0 to d (J).
double ObjectContactEnergy(const ObjectParams& object, double indentation_m);
// Whether one contact at this normal force and indentation has reached the damage criterion
// (force >= damage_force_n or indentation / half_width >= damage_strain). Always false for
// DamageMode::kNone and for non-finite inputs.
bool DamageReached(const ObjectParams& object, double normal_force_n, double indentation_m);
// stiffness *= factor (for the stability sweep).
ObjectParams WithStiffnessScale(ObjectParams object, double factor);

// d^exponent with exact fast paths for the exponents the fixtures use (1, 1.5, 2, 3). Inline,
// with the next function, because the grasp's series solve evaluates them in its inner loop.
inline double PowerOfIndentation(double d, double exponent) {
  if (exponent == 1.0) return d;
  if (exponent == 1.5) return d * std::sqrt(d);
  if (exponent == 2.0) return d * d;
  if (exponent == 3.0) return d * d * d;
  return std::pow(d, exponent);
}

// The force and dF/dd (into *stiffness) at once, with one power evaluation.
inline double ObjectContactForceAndStiffness(const ObjectParams& object, double d,
                                             double* stiffness) {
  if (!(d > 0)) {
    *stiffness = object.exponent == 1.0 ? object.stiffness : 0.0;
    return 0.0;
  }
  const double power = PowerOfIndentation(d, object.exponent);
  const double ratio = d / object.stiffening_length_m;  // 0 without stiffening (L = inf)
  const double stiffening = ratio * ratio;
  // d/dd [d^n (1 + s)] = n d^(n-1) (1 + s) + 2 s d^n / d, with s = d^2 / L^2.
  *stiffness =
      object.stiffness * (power / d) * (object.exponent * (1.0 + stiffening) + 2.0 * stiffening);
  return object.stiffness * power * (1.0 + stiffening);
}

}  // namespace hilrig::host

#endif  // HILRIG_HOST_PLANT_OBJECT_MODEL_H_
