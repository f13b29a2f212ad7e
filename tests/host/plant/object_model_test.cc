#include "host/plant/object_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ObjectParams Hertz() {
  ObjectParams object;
  object.stiffness = 1.5e7;
  object.exponent = 1.5;
  return object;
}

ObjectParams Stiffening() {
  ObjectParams object;
  object.stiffness = 630.0;
  object.stiffening_length_m = 0.010;
  return object;
}

TEST(ObjectModelTest, DefaultObjectValidates) { EXPECT_TRUE(ValidateObject(ObjectParams{}).ok()); }

void ExpectInvalid(const ObjectParams& object, const std::string& field) {
  const auto result = ValidateObject(object);
  ASSERT_FALSE(result.ok()) << field;
  EXPECT_NE(result.error().message.find(field), std::string::npos) << result.error().message;
}

TEST(ObjectModelTest, ValidateNamesTheBadField) {
  ObjectParams object;
  object.mass_kg = kNaN;
  ExpectInvalid(object, "mass_kg");
  object = {};
  object.half_width_m = 0.0;
  ExpectInvalid(object, "half_width_m");
  object = {};
  object.stiffness = kInf;
  ExpectInvalid(object, "stiffness");
  object = {};
  object.exponent = 0.5;
  ExpectInvalid(object, "exponent");
  object = {};
  object.friction_kinetic = 0.9;  // above the static 0.8
  ExpectInvalid(object, "friction_kinetic");
  object = {};
  object.damage_force_n = 0.0;
  ExpectInvalid(object, "damage_force_n");
  object = {};
  object.damage_strain = kNaN;
  ExpectInvalid(object, "damage_strain");
  object = {};
  object.stiffening_length_m = -1.0;
  ExpectInvalid(object, "stiffening_length_m");
  object = {};
  object.inertia_factor = -0.1;
  ExpectInvalid(object, "inertia_factor");
  object.inertia_factor = kNaN;
  ExpectInvalid(object, "inertia_factor");
}

TEST(ObjectModelTest, InfiniteLimitsAreAllowed) {
  ObjectParams object;
  object.damage_force_n = kInf;
  object.damage_strain = kInf;
  object.stiffening_length_m = kInf;
  EXPECT_TRUE(ValidateObject(object).ok());
}

TEST(ObjectModelTest, LinearForce) {
  const ObjectParams object;  // 1e3 N/m
  EXPECT_DOUBLE_EQ(ObjectContactForce(object, 0.002), 2.0);
}

TEST(ObjectModelTest, HertzForce) {
  // 1.5e7 x (1e-4)^1.5 = 1.5e7 x 1e-6 = 15 N: the egg's 150 N/mm secant at 0.1 mm.
  EXPECT_NEAR(ObjectContactForce(Hertz(), 1e-4), 15.0, 1e-12);
}

TEST(ObjectModelTest, StiffeningDoublesTheForceAtTheStiffeningLength) {
  EXPECT_NEAR(ObjectContactForce(Stiffening(), 0.010), 2.0 * 630.0 * 0.010, 1e-12);
}

TEST(ObjectModelTest, NoForceWithoutIndentation) {
  EXPECT_EQ(ObjectContactForce(Hertz(), 0.0), 0.0);
  EXPECT_EQ(ObjectContactForce(Hertz(), -1e-3), 0.0);
  EXPECT_EQ(ObjectContactForce(Hertz(), kNaN), 0.0);
}

TEST(ObjectModelTest, StiffnessIsTheDerivativeOfTheForce) {
  ObjectParams mixed = Hertz();
  mixed.stiffening_length_m = 2e-4;
  for (const ObjectParams& object : {ObjectParams{}, Hertz(), Stiffening(), mixed}) {
    for (double d : {1e-5, 1e-4, 3e-3}) {
      const double h = d * 1e-5;
      const double numeric =
          (ObjectContactForce(object, d + h) - ObjectContactForce(object, d - h)) / (2 * h);
      EXPECT_NEAR(ObjectContactStiffness(object, d), numeric, 1e-6 * numeric) << d;
    }
  }
}

TEST(ObjectModelTest, EnergyIsTheIntegralOfTheForce) {
  for (const ObjectParams& object : {ObjectParams{}, Hertz(), Stiffening()}) {
    const double d = 2e-3;
    const int n = 2000;  // Simpson
    double sum = ObjectContactForce(object, 0.0) + ObjectContactForce(object, d);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * ObjectContactForce(object, d * i / n);
    const double integral = sum * d / n / 3.0;
    EXPECT_NEAR(ObjectContactEnergy(object, d), integral, 1e-9 * integral);
  }
}

TEST(ObjectModelTest, DamageByForce) {
  ObjectParams object;
  object.damage_mode = DamageMode::kBurst;
  object.damage_force_n = 0.45;
  EXPECT_FALSE(DamageReached(object, 0.44, 0.0));
  EXPECT_TRUE(DamageReached(object, 0.45, 0.0));
}

TEST(ObjectModelTest, DamageByStrain) {
  ObjectParams object;  // half width 30 mm
  object.damage_mode = DamageMode::kCrush;
  object.damage_strain = 0.5;
  EXPECT_FALSE(DamageReached(object, 100.0, 0.0149));
  EXPECT_TRUE(DamageReached(object, 0.0, 0.015));
}

TEST(ObjectModelTest, UndamageableObjectsAndNaNNeverDamage) {
  ObjectParams object;
  object.damage_force_n = 0.1;
  EXPECT_FALSE(DamageReached(object, 100.0, 0.1));  // kNone
  object.damage_mode = DamageMode::kCrack;
  EXPECT_FALSE(DamageReached(object, kNaN, kNaN));
}

TEST(ObjectModelTest, StiffnessScale) {
  EXPECT_EQ(WithStiffnessScale(ObjectParams{}, 10.0).stiffness, 1e4);
}

TEST(ObjectModelTest, DamageModeNames) {
  EXPECT_STREQ(DamageModeName(DamageMode::kNone), "none");
  EXPECT_STREQ(DamageModeName(DamageMode::kBurst), "burst");
  EXPECT_STREQ(DamageModeName(DamageMode::kCrack), "crack");
  EXPECT_STREQ(DamageModeName(DamageMode::kShatter), "shatter");
  EXPECT_STREQ(DamageModeName(DamageMode::kCrush), "crush");
}

}  // namespace
}  // namespace hilrig::host
