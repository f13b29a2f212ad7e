#include "host/plant/grasp_contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "host/sensors/tactile/sensor_layout.h"

namespace hilrig::host {
namespace {

constexpr double kDt = 1e-3;
constexpr double kG = 9.81;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPadK = 5.6e3;
constexpr double kShearK = 6 * 1.5e3;

// A 50 g linear object 60 mm across, friction 0.8 / 0.6, stand at 0.5 m.
GraspSceneParams Scene() {
  GraspSceneParams scene;
  scene.object.name = "test_object";
  scene.object.mass_kg = 0.05;
  scene.object.half_width_m = 0.030;
  scene.object.stiffness = 2000.0;
  return scene;
}

// Frame angle that overlaps the object by `overlap_m` at every pad.
double AngleForOverlap(const GraspSceneParams& scene, double overlap_m) {
  return AngleForPadRadius(scene.frame, scene.object.half_width_m - overlap_m);
}

// Per-pad force of the linear test object: springs in series.
double LinearSeriesForce(double object_k, double overlap_m) {
  return overlap_m * object_k * kPadK / (object_k + kPadK);
}

GraspVehicleSample HoverAt(double z_m) {
  GraspVehicleSample vehicle;
  vehicle.position_m = {0.3, -0.2, z_m};
  return vehicle;
}

// Independent reference for the series contact: bisection on the force, inverting each side's
// law by bisection, until the two compressions add up to the overlap.
double InvertByBisection(double force, double hi, auto law) {
  double lo = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (law(mid) < force ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double ReferenceSeriesForce(double k, double n, double length, double pad_k, double beta,
                            double overlap) {
  auto object = [&](double d) { return k * std::pow(d, n) * (1 + (d / length) * (d / length)); };
  auto pad = [&](double d) { return pad_k * d * (1 + beta * d * d); };
  double lo = 0.0;
  double hi = std::min(object(overlap), pad(overlap));
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double total =
        InvertByBisection(mid, overlap, object) + InvertByBisection(mid, overlap, pad);
    (total < overlap ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// ---------------------------------------------------------------------------------------------
// Series contact

TEST(SeriesContactTest, LinearLinearMatchesClosedForm) {
  ObjectParams object;
  object.stiffness = 1000.0;
  const SeriesContact c = SolveSeriesContact(object, kPadK, 0.0, 1e-3);
  EXPECT_NEAR(c.force_n, 1e-3 * 1000.0 * 5600.0 / 6600.0, 1e-15);
  EXPECT_NEAR(c.indentation_m, 1e-3 * 5600.0 / 6600.0, 1e-15);
  EXPECT_NEAR(c.pad_compression_m + c.indentation_m, 1e-3, 1e-18);
}

TEST(SeriesContactTest, NoOverlapNoForce) {
  const SeriesContact c = SolveSeriesContact(ObjectParams{}, kPadK, 0.0, -1e-3);
  EXPECT_EQ(c.force_n, 0.0);
  EXPECT_EQ(c.indentation_m, 0.0);
}

TEST(SeriesContactTest, HertzObjectMatchesBisection) {
  ObjectParams object;
  object.stiffness = 1.5e7;  // the egg
  object.exponent = 1.5;
  for (double overlap : {1e-6, 1e-4, 1e-3, 5e-3}) {
    const SeriesContact c = SolveSeriesContact(object, kPadK, 0.0, overlap);
    const double reference = ReferenceSeriesForce(1.5e7, 1.5, 1e300, kPadK, 0.0, overlap);
    EXPECT_NEAR(c.force_n, reference, 1e-9 * reference) << overlap;
    // The split is consistent: both sides carry the same force.
    EXPECT_NEAR(ObjectContactForce(object, c.indentation_m), reference, 1e-6 * reference);
  }
}

TEST(SeriesContactTest, StiffeningBothSidesMatchesBisection) {
  ObjectParams object;
  object.stiffness = 630.0;  // the balloon
  object.stiffening_length_m = 0.010;
  const double beta = 1.0 / (0.0035 * 0.0035);
  for (double overlap : {1e-4, 3e-3, 1.5e-2}) {
    const SeriesContact c = SolveSeriesContact(object, kPadK, beta, overlap);
    const double reference = ReferenceSeriesForce(630.0, 1.0, 0.010, kPadK, beta, overlap);
    EXPECT_NEAR(c.force_n, reference, 1e-9 * reference) << overlap;
  }
}

TEST(SeriesContactTest, AccurateOverTheWholeStiffnessRange) {
  for (double exponent : {1.0, 1.5, 2.3}) {
    for (double k = 1e-2; k <= 1e9 * 1.0001; k *= 10.0) {
      ObjectParams object;
      object.stiffness = k;
      object.exponent = exponent;
      object.stiffening_length_m = 0.02;  // keeps the linear case off the closed form
      const SeriesContact c = SolveSeriesContact(object, kPadK, 0.0, 2e-3);
      const double reference = ReferenceSeriesForce(k, exponent, 0.02, kPadK, 0.0, 2e-3);
      ASSERT_TRUE(std::isfinite(c.force_n));
      EXPECT_NEAR(c.force_n, reference, 1e-9 * reference) << "k " << k << " n " << exponent;
    }
  }
}

TEST(SeriesContactTest, ScaledStiffnessGivesFiniteMonotoneForces) {
  ObjectParams base;
  base.stiffness = 1.4e8;  // the glass cup
  base.exponent = 1.5;
  for (double scale = 1e-3; scale <= 1e3 * 1.0001; scale *= 10.0) {
    const ObjectParams object = WithStiffnessScale(base, scale);
    double previous = 0.0;
    for (double overlap = 1e-5; overlap < 2e-2; overlap *= 1.5) {
      const double force = SolveSeriesContact(object, kPadK, 0.0, overlap).force_n;
      ASSERT_TRUE(std::isfinite(force));
      EXPECT_GT(force, previous) << scale << " " << overlap;
      EXPECT_LT(force, kPadK * overlap);  // never stiffer than the pad alone
      previous = force;
    }
  }
}

TEST(SeriesContactTest, WarmStartDoesNotChangeTheAnswer) {
  ObjectParams object;
  object.stiffness = 1.4e8;  // the glass cup
  object.exponent = 1.5;
  const double cold = SolveSeriesContact(object, kPadK, 0.0, 1e-3).force_n;
  // Seeds that predict the object's share of the overlap anywhere in (0, 1), outside it, or NaN.
  for (double share : {1e-9, 0.01, 0.5, 0.999999, -1.0, 2.0, kNaN}) {
    const SeriesSeed seed{.overlap_m = 1e-3, .indentation_m = share * 1e-3};
    EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, 1e-3, seed).force_n, cold, 1e-12 * cold)
        << share;
  }
}

// The balloon's law: linear with membrane stiffening over 10 mm.
ObjectParams StiffeningObject() {
  ObjectParams object;
  object.stiffness = 628.0;
  object.stiffening_length_m = 0.010;
  return object;
}

TEST(SeriesContactTest, SeededSolveMatchesTheReference) {
  const ObjectParams object = StiffeningObject();
  const double overlap = 2e-3;
  const double reference = ReferenceSeriesForce(628.0, 1.0, 0.010, kPadK, 0.0, overlap);
  const SeriesSeed near{overlap - 1e-6, 1.5e-3, 0.9};
  const SeriesSeed far{1e-5, 1e-5, 0.5};
  const SeriesSeed outside{overlap, 5e-3, 0.0};  // predicts more indentation than the overlap
  const SeriesSeed not_finite{overlap, kNaN, kNaN};
  for (const SeriesSeed& seed : {SeriesSeed{}, near, far, outside, not_finite}) {
    EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, overlap, seed).force_n, reference,
                1e-9 * reference)
        << seed.overlap_m << " " << seed.indentation_m;
  }
}

TEST(SeriesContactTest, IndentationPerOverlapIsTheDerivative) {
  const ObjectParams object = StiffeningObject();
  const double overlap = 2e-3;
  const double h = 1e-9;
  const double numeric = (SolveSeriesContact(object, kPadK, 0.0, overlap + h).indentation_m -
                          SolveSeriesContact(object, kPadK, 0.0, overlap - h).indentation_m) /
                         (2 * h);
  EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, overlap).indentation_per_overlap, numeric,
              1e-5);
  // Linear against linear: the object takes k_pad / (k_object + k_pad) of any change.
  EXPECT_NEAR(SolveSeriesContact(ObjectParams{}, kPadK, 0.0, overlap).indentation_per_overlap,
              kPadK / (1e3 + kPadK), 1e-15);
}

TEST(SeriesContactTest, SeedKeepsTheSolveAndItsSlope) {
  const SeriesContact contact = SolveSeriesContact(StiffeningObject(), kPadK, 0.0, 2e-3);
  const SeriesSeed seed = SeedOf(contact, 2e-3);
  EXPECT_EQ(seed.overlap_m, 2e-3);
  EXPECT_EQ(seed.indentation_m, contact.indentation_m);
  EXPECT_EQ(seed.indentation_per_overlap, contact.indentation_per_overlap);
  EXPECT_EQ(SeedOf(contact, 0.0).overlap_m, 0.0);  // no contact: nothing to start from
  EXPECT_EQ(SeedOf(contact, kNaN).overlap_m, 0.0);
}

TEST(SeriesContactTest, SeedKeepsTheWholeSolveForTheSameOverlap) {
  const ObjectParams object = StiffeningObject();
  const double reference = ReferenceSeriesForce(628.0, 1.0, 0.010, kPadK, 0.0, 2e-3);
  const SeriesSeed seed = SeedOf(SolveSeriesContact(object, kPadK, 0.0, 2e-3), 2e-3);
  ASSERT_TRUE(seed.has_solve);
  EXPECT_NEAR(seed.solve.force_n, reference, 1e-9 * reference);
  const SeriesContact again = SolveSeriesContact(object, kPadK, 0.0, 2e-3, seed);
  EXPECT_NEAR(again.force_n, reference, 1e-9 * reference);
  EXPECT_NEAR(again.indentation_m + again.pad_compression_m, 2e-3, 1e-18);
}

TEST(SeriesContactTest, KeptSolveIsReturnedOnlyAtItsOwnOverlap) {
  // A kept solve with a marker force: the same overlap returns it untouched, any other overlap
  // (even one ulp away) solves.
  const ObjectParams object = StiffeningObject();
  SeriesSeed seed = SeedOf(SolveSeriesContact(object, kPadK, 0.0, 2e-3), 2e-3);
  seed.solve.force_n = 123.0;
  EXPECT_EQ(SolveSeriesContact(object, kPadK, 0.0, 2e-3, seed).force_n, 123.0);
  const double next = std::nextafter(2e-3, 1.0);
  const double reference = ReferenceSeriesForce(628.0, 1.0, 0.010, kPadK, 0.0, next);
  EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, next, seed).force_n, reference,
              1e-9 * reference);
  // A hand-made seed at the same overlap keeps no solve: it only starts the iteration, which
  // converges to the force there.
  const SeriesSeed hand_made{2e-3, 1.5e-3, 0.9};
  const double at_seed = ReferenceSeriesForce(628.0, 1.0, 0.010, kPadK, 0.0, 2e-3);
  EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, 2e-3, hand_made).force_n, at_seed,
              1e-9 * at_seed);
}

TEST(GraspSceneConstantsTest, FirstPadDirectionAndUsability) {
  const GraspSceneConstants constants = MakeGraspSceneConstants(Scene());
  EXPECT_TRUE(constants.scene_usable);
  // Default first azimuth 30 deg.
  EXPECT_NEAR(constants.outward_x[0], std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(constants.outward_y[0], 0.5, 1e-15);
}

// The steps and the servo load use the scene exactly when its validator passes: one check, so a
// field the message names is never one the per-tick paths still use.
TEST(GraspSceneConstantsTest, UsableExactlyWhenTheSceneIsValid) {
  const std::vector<std::pair<const char*, void (*)(GraspSceneParams&)>> breaks = {
      {"mass", [](GraspSceneParams& s) { s.object.mass_kg = 0.0; }},
      {"stiffness", [](GraspSceneParams& s) { s.object.stiffness = -1.0; }},
      {"friction", [](GraspSceneParams& s) { s.object.friction_kinetic = 10.0; }},
      {"damage", [](GraspSceneParams& s) { s.object.damage_force_n = 0.0; }},
      {"standoff", [](GraspSceneParams& s) { s.frame.film_standoff_m = kNaN; }},
      {"shear pad", [](GraspSceneParams& s) { s.pad_stiffness_n_per_m.y() = kNaN; }},
      {"beta", [](GraspSceneParams& s) { s.pad_stiffening_per_m2 = -1.0; }},
      {"stand", [](GraspSceneParams& s) { s.stand_height_m = kNaN; }},
  };
  for (const auto& [name, spoil] : breaks) {
    GraspSceneParams scene = Scene();
    spoil(scene);
    ASSERT_FALSE(ValidateGraspScene(scene).ok()) << name;
    EXPECT_FALSE(MakeGraspSceneConstants(scene).scene_usable) << name;
    GraspState state = InitialGraspState(Scene());  // an object the valid scene put there
    const double angle = AngleForOverlap(Scene(), 2e-3);
    EXPECT_EQ(SymmetricNormalForce(scene, state, angle), 0.0) << name;
    EXPECT_EQ(GraspServoLoad(scene, state).TorqueAt(angle), 0.0) << name;
  }
}

TEST(GraspSceneConstantsTest, PadDirectionsStep60DegreesFromTheFirst) {
  const GraspSceneConstants constants = MakeGraspSceneConstants(Scene());
  // Default first azimuth 30 deg: pads at 30, 90, ..., 330 deg.
  for (int i = 0; i < kGripperPadCount; ++i) {
    const double azimuth = (30.0 + 60.0 * i) * std::numbers::pi / 180.0;
    EXPECT_NEAR(constants.outward_x[i], std::cos(azimuth), 1e-15) << i;
    EXPECT_NEAR(constants.outward_y[i], std::sin(azimuth), 1e-15) << i;
  }
}

TEST(GraspSceneConstantsTest, UnusableConstantsGiveNoForces) {
  GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const GraspSceneConstants unusable;  // default: nothing usable
  const GraspForces forces =
      StepGrasp(scene, unusable, state, HoverAt(0.5), AngleForOverlap(scene, 2e-3), kDt);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_EQ(GraspServoLoad(scene, unusable, state).TorqueAt(AngleForOverlap(scene, 2e-3)), 0.0);
}

TEST(GraspContactTest, ServoLoadSeedsEachSolveFromTheLastWithoutChangingIt) {
  GraspSceneParams scene = Scene();
  scene.object = StiffeningObject();
  scene.object.half_width_m = 0.040;
  const GraspState state = InitialGraspState(scene);
  const GraspServoLoad load(scene, state);
  // A search-like sequence: far apart, then converging; every torque is the reference's.
  for (double overlap : {2e-3, 1e-4, 3e-3, 2.5e-3, 2.4e-3, 2.4000001e-3}) {
    const double reference =
        0.025 * 6 * ReferenceSeriesForce(628.0, 1.0, 0.010, kPadK, 0.0, overlap);
    double slope = 0.0;
    EXPECT_NEAR(load.TorqueAndSlopeAt(AngleForOverlap(scene, overlap), &slope), reference,
                1e-9 * reference)
        << overlap;
  }
}

TEST(SeriesContactTest, SeriesStiffnessIsTheDerivative) {
  ObjectParams object;
  object.stiffness = 1.5e7;
  object.exponent = 1.5;
  const double overlap = 1e-3;
  const double h = 1e-9;
  const double numeric = (SolveSeriesContact(object, kPadK, 0.0, overlap + h).force_n -
                          SolveSeriesContact(object, kPadK, 0.0, overlap - h).force_n) /
                         (2 * h);
  EXPECT_NEAR(SolveSeriesContact(object, kPadK, 0.0, overlap).stiffness_n_per_m, numeric,
              1e-5 * numeric);
}

// ---------------------------------------------------------------------------------------------
// Symmetric squeeze and the servo load

TEST(GraspContactTest, SymmetricForceFromTheFrameAngle) {
  const GraspSceneParams scene = Scene();
  const GraspState state = InitialGraspState(scene);
  double indentation = 0.0;
  const double force =
      SymmetricNormalForce(scene, state, AngleForOverlap(scene, 2e-3), &indentation);
  EXPECT_NEAR(force, LinearSeriesForce(2000.0, 2e-3), 1e-12);
  EXPECT_NEAR(indentation, 2e-3 * kPadK / (2000.0 + kPadK), 1e-15);
  EXPECT_EQ(SymmetricNormalForce(scene, state, AngleForOverlap(scene, -1e-3)), 0.0);
}

TEST(GraspContactTest, NoForceWhenDroppedDestroyedOrNaN) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  EXPECT_EQ(SymmetricNormalForce(scene, state, kNaN), 0.0);
  for (GraspMode mode : {GraspMode::kDropped, GraspMode::kDestroyed, GraspMode::kNoObject}) {
    state.mode = mode;
    EXPECT_EQ(SymmetricNormalForce(scene, state, angle), 0.0) << GraspModeName(mode);
    EXPECT_EQ(GraspServoLoad(scene, state).TorqueAt(angle), 0.0);
  }
}

TEST(GraspContactTest, ServoLoadIsClosingTimesTheGraspForce) {
  const GraspSceneParams scene = Scene();
  const GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  const GraspServoLoad load(scene, state);
  EXPECT_NEAR(load.TorqueAt(angle), 0.025 * 6 * LinearSeriesForce(2000.0, 2e-3), 1e-14);
  double slope = 0.0;
  load.TorqueAndSlopeAt(angle, &slope);
  EXPECT_NEAR(slope, 0.025 * 0.025 * 6 * 2000.0 * kPadK / (2000.0 + kPadK), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Stability sweep: the servo closes the frame on the object with quasi-static contact.

void RunClosingSweep(ObjectParams object) {
  object.damage_mode = DamageMode::kNone;  // squeeze to the servo's ceiling without breaking
  GraspSceneParams scene;
  scene.object = object;
  const ServoParams servo;
  GraspState grasp = InitialGraspState(scene);
  ServoState servo_state;
  const GraspVehicleSample vehicle = HoverAt(scene.stand_height_m);
  const double per_pad_ceiling = servo.stall_torque_nm / scene.frame.closing_m_per_rad / 6.0;
  const double energy_ceiling =
      servo.stall_torque_nm * (servo.max_angle_rad - servo.min_angle_rad) + 1e-9;
  double previous_force = 0.0;
  double last_force = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const GraspServoLoad load(scene, grasp);
    servo_state = StepServo(servo, servo_state, 1.2, load, kDt);
    const GraspForces forces = StepGrasp(scene, grasp, vehicle, servo_state.angle_rad, kDt);
    ASSERT_TRUE(std::isfinite(servo_state.angle_rad));
    ASSERT_TRUE(std::isfinite(forces.elastic_energy_j));
    ASSERT_TRUE(forces.force_on_vehicle_world_n.allFinite());
    for (int p = 0; p < kGripperPadCount; ++p) {
      ASSERT_TRUE(forces.pad_force_n[p].allFinite());
      ASSERT_LE(forces.normal_force_n[p], 1.01 * per_pad_ceiling) << "step " << i;
    }
    ASSERT_LE(forces.elastic_energy_j, energy_ceiling) << "step " << i;
    // Closing monotonically: the force never rings back.
    ASSERT_GE(forces.normal_force_n[0], previous_force - 1e-9) << "step " << i;
    previous_force = forces.normal_force_n[0];
    last_force = forces.normal_force_n[0];
  }
  EXPECT_EQ(grasp.mode, GraspMode::kOnStand);
  EXPECT_TRUE(servo_state.stalled);
  // Commanded 1.2 rad, far past contact: the servo ends at its stall torque.
  EXPECT_NEAR(last_force, per_pad_ceiling, 1e-3 * per_pad_ceiling);
}

ObjectParams Balloon() {
  ObjectParams o;
  o.mass_kg = 0.003;
  o.half_width_m = 0.040;
  o.stiffness = 628.0;
  o.stiffening_length_m = 0.010;
  return o;
}

ObjectParams GlassCup() {
  ObjectParams o;
  o.mass_kg = 0.150;
  o.half_width_m = 0.035;
  o.stiffness = 1.414e8;
  o.exponent = 1.5;
  return o;
}

TEST(GraspStabilityTest, BalloonSofter) { RunClosingSweep(WithStiffnessScale(Balloon(), 0.1)); }
TEST(GraspStabilityTest, Balloon) { RunClosingSweep(Balloon()); }
TEST(GraspStabilityTest, BalloonStiffer) { RunClosingSweep(WithStiffnessScale(Balloon(), 10)); }
TEST(GraspStabilityTest, GlassCupSofter) { RunClosingSweep(WithStiffnessScale(GlassCup(), 0.1)); }
TEST(GraspStabilityTest, GlassCup) { RunClosingSweep(GlassCup()); }
TEST(GraspStabilityTest, GlassCupStiffer) { RunClosingSweep(WithStiffnessScale(GlassCup(), 10)); }

// ---------------------------------------------------------------------------------------------
// Modes

TEST(GraspContactTest, StartsOnTheStand) {
  const GraspState state = InitialGraspState(Scene());
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_EQ(state.object_mass_kg, 0.05);
  EXPECT_EQ(state.object_height_m, 0.5);
  EXPECT_FALSE(state.gripped);
}

TEST(GraspContactTest, InvalidSceneHasNoObject) {
  GraspSceneParams scene = Scene();
  scene.object.stiffness = kNaN;
  EXPECT_EQ(InitialGraspState(scene).mode, GraspMode::kNoObject);
  EXPECT_FALSE(ValidateGraspScene(scene).ok());
  EXPECT_NE(ValidateGraspScene(scene).error().message.find("stiffness"), std::string::npos);
}

TEST(GraspContactTest, OpenFrameOnTheStandCarriesNothing) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.5), 0.0, kDt);
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_FALSE(state.gripped);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_EQ(forces.force_on_vehicle_world_n, Eigen::Vector3d::Zero());
}

TEST(GraspContactTest, GripOnTheStandStartsWithoutShear) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const GraspForces forces =
      StepGrasp(scene, state, HoverAt(0.503), AngleForOverlap(scene, 2e-3), kDt);
  EXPECT_TRUE(state.gripped);
  EXPECT_NEAR(state.stand_anchor_m, 0.003, 1e-15);
  EXPECT_EQ(forces.shear_force_n, 0.0);
  EXPECT_NEAR(forces.grasp_force_n, 6 * LinearSeriesForce(2000.0, 2e-3), 1e-12);
}

TEST(GraspContactTest, StickLawOnTheStandBelowTheWeight) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.50001), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_NEAR(forces.shear_force_n, kShearK * 1e-5, 1e-9);  // 0.09 N < 0.49 N weight
  EXPECT_NEAR(forces.force_on_vehicle_world_n.z(), -kShearK * 1e-5, 1e-9);
  EXPECT_EQ(forces.payload_mass_kg, 0.0);
}

TEST(GraspContactTest, RisingFrameLiftsAWellGrippedObject) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);  // 6 x 2.96 N x 0.8 >> 0.49 N
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.502), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
  EXPECT_NEAR(forces.shear_force_n, 0.05 * kG, 1e-12);
  EXPECT_EQ(forces.payload_mass_kg, 0.05);
  EXPECT_EQ(forces.force_on_vehicle_world_n, Eigen::Vector3d::Zero());
}

TEST(GraspContactTest, TakingTheStandAwayHangsAWellGrippedObjectOnThePads) {
  GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);  // friction capacity >> the 0.49 N weight
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  scene.stand_present = false;
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
  EXPECT_NEAR(forces.shear_force_n, 0.05 * kG, 1e-12);
  EXPECT_EQ(forces.payload_mass_kg, 0.05);
  // Lowered far below where the stand was, it stays held: nothing is there to put it back on.
  StepGrasp(scene, state, HoverAt(0.2), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
}

// The pads reach an object on its stand only within its half height (30 mm) plus theirs (10 mm)
// of its centre: 20 cm below it the frame closes on nothing, the servo feels no load, and taking
// the stand away leaves the object where it was instead of hanging it on the pads.
TEST(GraspContactTest, PadsFarBelowTheObjectGripNothing) {
  GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  const GraspVehicleSample below = HoverAt(scene.stand_height_m - 0.20);
  GraspForces forces = StepGrasp(scene, state, below, angle, kDt);
  EXPECT_TRUE(state.out_of_reach);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_FALSE(state.gripped);
  EXPECT_EQ(GraspServoLoad(scene, state).TorqueAt(angle), 0.0);
  scene.stand_present = false;
  forces = StepGrasp(scene, state, below, angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kDropped);
  EXPECT_EQ(forces.payload_mass_kg, 0.0);
  EXPECT_EQ(forces.payload_inertia_kg_m2, Eigen::Vector3d::Zero());
}

TEST(GraspContactTest, PadsReachTheObjectWithinItsHalfHeightPlusTheirs) {
  const GraspSceneParams scene = Scene();  // half height 30 mm, pads 10 mm
  EXPECT_TRUE(PadsReach(scene, 0.5, 0.5));
  EXPECT_TRUE(PadsReach(scene, 0.5 - 0.0399, 0.5));
  EXPECT_TRUE(PadsReach(scene, 0.5 + 0.0399, 0.5));
  EXPECT_FALSE(PadsReach(scene, 0.5 - 0.0401, 0.5));
  EXPECT_FALSE(PadsReach(scene, 0.5 + 0.0401, 0.5));
  EXPECT_FALSE(PadsReach(scene, kNaN, 0.5));
  // Within reach, off centre, the grip is the symmetric squeeze it always was.
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  const GraspForces forces =
      StepGrasp(scene, state, HoverAt(scene.stand_height_m - 0.035), angle, kDt);
  EXPECT_FALSE(state.out_of_reach);
  EXPECT_NEAR(forces.grasp_force_n, 6 * LinearSeriesForce(2000.0, 2e-3), 1e-12);
}

TEST(GraspContactTest, TakingTheStandAwayFromAnUngrippedObjectDropsIt) {
  GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  scene.stand_present = false;
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.5), 0.0, kDt);
  EXPECT_EQ(state.mode, GraspMode::kDropped);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_EQ(forces.payload_mass_kg, 0.0);
}

TEST(GraspContactTest, TakingTheStandAwayFromAWeakGripStartsASlide) {
  GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 5e-6);  // 36 mN of friction for 0.49 N of weight
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  scene.stand_present = false;
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kSliding);
}

TEST(GraspContactTest, WeakGripSlidesOverTheObjectOnTheStand) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double overlap = 5e-6;  // 6 x 0.8 x 7.4 mN = 36 mN < 0.49 N
  const double angle = AngleForOverlap(scene, overlap);
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.502), angle, kDt);
  const double cap = 0.8 * 6 * LinearSeriesForce(2000.0, overlap);
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_EQ(state.object_height_m, 0.5);
  EXPECT_NEAR(forces.shear_force_n, cap, 1e-12);
  EXPECT_NEAR(forces.force_on_vehicle_world_n.z(), -cap, 1e-12);
  EXPECT_NEAR(state.stand_anchor_m, 0.002 - cap / kShearK, 1e-12);  // the pads slid up
}

// A held object at 1 m with the grip of `overlap_m`.
GraspState HeldState(const GraspSceneParams& scene) {
  GraspState state = InitialGraspState(scene);
  state.mode = GraspMode::kHeld;
  state.gripped = true;
  state.stand_anchor_m = 0.0;
  state.object_height_m = 1.0;
  return state;
}

TEST(GraspContactTest, HeldInHoverPadSignsCarryTheWeight) {
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  const GraspForces forces =
      StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 2e-3), kDt);
  ASSERT_EQ(state.mode, GraspMode::kHeld);
  double sum_y = 0.0;
  for (int i = 0; i < kGripperPadCount; ++i) {
    EXPECT_LT(forces.pad_force_n[i].y(), 0.0) << i;  // the object pulls the films down
    EXPECT_EQ(forces.pad_force_n[i].x(), 0.0);
    EXPECT_EQ(forces.pad_force_n[i].z(), forces.normal_force_n[i]);
    EXPECT_GT(forces.pad_force_n[i].z(), 0.0);
    sum_y += forces.pad_force_n[i].y();
  }
  EXPECT_NEAR(sum_y, -0.05 * kG, 1e-9 * 0.05 * kG);
  EXPECT_NEAR(forces.shear_force_n, 0.05 * kG, 1e-12);
}

TEST(GraspContactTest, HeldPadForcesReadAsTheWeightThroughTheSensorFrames) {
  // Rotating each pad's film force into the body with the sensor layout's mounting and adding
  // them up gives the object's weight pulling down (and no net horizontal force).
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  const GraspForces forces =
      StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 2e-3), kDt);
  const auto layout = DefaultTactileLayout();
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int i = 0; i < kGripperPadCount; ++i) {
    total += layout[i].mounting_body_from_sensor * forces.pad_force_n[i];
  }
  EXPECT_LT((total - Eigen::Vector3d(0, 0, -0.05 * kG)).norm(), 1e-12);
}

TEST(GraspContactTest, HeldHorizontalAccelerationIsCarriedByNormalImbalance) {
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  GraspVehicleSample vehicle = HoverAt(1.0);
  vehicle.specific_force_body_m_s2 = {1.0, 0.0, kG};
  const GraspForces forces = StepGrasp(scene, state, vehicle, AngleForOverlap(scene, 2e-3), kDt);
  ASSERT_EQ(state.mode, GraspMode::kHeld);
  // Force of the pads on the object: each pushes inward (-o_i) with its normal force.
  Eigen::Vector3d on_object = Eigen::Vector3d::Zero();
  for (int i = 0; i < kGripperPadCount; ++i) {
    on_object -= forces.normal_force_n[i] * PadOutwardBody(scene.frame, i);
  }
  EXPECT_NEAR(on_object.x(), 0.05 * 1.0, 1e-12);
  EXPECT_NEAR(on_object.y(), 0.0, 1e-12);
  EXPECT_NEAR(forces.grasp_force_n, 6 * LinearSeriesForce(2000.0, 2e-3), 1e-12);
  // The pads on the -x side (azimuths 150, 210 deg) press harder.
  EXPECT_GT(forces.normal_force_n[2], forces.normal_force_n[0]);
}

// Force of the pads on the object in the body frame: each pushes inward (-o_i) with its normal.
Eigen::Vector3d PadsOnObject(const GraspSceneParams& scene, const GraspForces& forces) {
  Eigen::Vector3d on_object = Eigen::Vector3d::Zero();
  for (int i = 0; i < kGripperPadCount; ++i) {
    on_object -= forces.normal_force_n[i] * PadOutwardBody(scene.frame, i);
  }
  return on_object;
}

TEST(GraspContactTest, PadsThatWouldPullLetGoAndThoseLeftStillCarryTheHold) {
  // A light squeeze (0.147 N per pad at 0.1 mm) against a hard sideways push: with all six pads in
  // contact the two on the push side would have to pull.
  const GraspSceneParams scene = Scene();
  const double overlap = 1e-4;
  const double n0 = LinearSeriesForce(2000.0, overlap);
  struct Push {
    double accel_m_s2;
    double azimuth_rad;
    int released;
  };
  // Along pad 0's and pad 5's bisector the two pads on the push side let go; at 37 deg the object's
  // shift onto the four left also unloads pad 1, which alone would still have pressed; a push 10 g
  // hard leaves three pads carrying it.
  for (const Push& push : {Push{20.0, 0.0, 2}, Push{20.0, 0.65, 3}, Push{200.0, 0.3, 3}}) {
    GraspState state = HeldState(scene);
    GraspVehicleSample vehicle = HoverAt(1.0);
    const Eigen::Vector3d accel_m_s2(push.accel_m_s2 * std::cos(push.azimuth_rad),
                                     push.accel_m_s2 * std::sin(push.azimuth_rad), kG);
    vehicle.specific_force_body_m_s2 = accel_m_s2;
    const GraspForces forces =
        StepGrasp(scene, state, vehicle, AngleForOverlap(scene, overlap), kDt);
    ASSERT_EQ(state.mode, GraspMode::kHeld);
    // The pads apply the whole horizontal push, none of them pulling.
    const Eigen::Vector3d on_object = PadsOnObject(scene, forces);
    EXPECT_NEAR(on_object.x(), 0.05 * accel_m_s2.x(), 1e-12) << push.azimuth_rad;
    EXPECT_NEAR(on_object.y(), 0.05 * accel_m_s2.y(), 1e-12) << push.azimuth_rad;
    int released = 0;
    for (int i = 0; i < kGripperPadCount; ++i) {
      EXPECT_GE(forces.normal_force_n[i], 0.0) << i;
      released += forces.normal_force_n[i] == 0.0 ? 1 : 0;
      // Every pad whose share of the push exceeds its squeeze has let go.
      const Eigen::Vector3d outward = PadOutwardBody(scene.frame, i);
      if (n0 < outward.dot(0.05 * accel_m_s2) / 3.0) {
        EXPECT_EQ(forces.normal_force_n[i], 0.0) << i;
      }
    }
    EXPECT_EQ(released, push.released) << push.azimuth_rad;
    EXPECT_EQ(forces.released_pads, push.released) << push.azimuth_rad;
    EXPECT_LT(forces.unbalanced_horizontal_n, 1e-12);
    // The frame holds every pad's push: the pads still touching press more than the six equal
    // squeezes would, and the servo's load says so.
    double sum_n = 0.0;
    for (const double normal : forces.normal_force_n) sum_n += normal;
    EXPECT_GT(sum_n, kGripperPadCount * n0 * 1.01) << push.azimuth_rad;
    const GraspServoLoad load(scene, state);
    EXPECT_NEAR(load.TorqueAt(AngleForOverlap(scene, overlap)),
                scene.frame.closing_m_per_rad * sum_n, 1e-9 * sum_n)
        << push.azimuth_rad;
  }
}

TEST(GraspContactTest, LoweringAHeldObjectPutsItBackOnTheStand) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  StepGrasp(scene, state, HoverAt(0.502), angle, kDt);
  ASSERT_EQ(state.mode, GraspMode::kHeld);
  StepGrasp(scene, state, HoverAt(0.501), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);  // object centre still 1 mm - 0.05 mm above the stand
  const GraspForces forces = StepGrasp(scene, state, HoverAt(0.4999), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_EQ(state.object_height_m, 0.5);
  EXPECT_EQ(forces.payload_mass_kg, 0.0);
  EXPECT_LT(forces.shear_force_n, 0.05 * kG);
}

TEST(GraspContactTest, WeakGripSlidesWithKineticFrictionThenDrops) {
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  const double overlap = 3e-5;  // per pad 44.5 mN, mu_s x grasp = 0.21 N < 0.49 N
  const double angle = AngleForOverlap(scene, overlap);
  const double grasp = 6 * LinearSeriesForce(2000.0, overlap);
  const double accel = kG - 0.6 * grasp / 0.05;
  GraspForces forces = StepGrasp(scene, state, HoverAt(1.0), angle, kDt);
  ASSERT_EQ(state.mode, GraspMode::kSliding);
  EXPECT_NEAR(forces.shear_force_n, 0.6 * grasp, 1e-12);
  EXPECT_NEAR(forces.force_on_vehicle_world_n.z(), -0.6 * grasp, 1e-12);
  EXPECT_EQ(forces.payload_mass_kg, 0.0);
  int steps = 1;
  while (state.mode == GraspMode::kSliding && steps < 1000) {
    forces = StepGrasp(scene, state, HoverAt(1.0), angle, kDt);
    ++steps;
    if (steps == 20) {
      // Semi-implicit Euler of a constant acceleration: v_n = -a n dt, s_n = -a dt^2 n (n+1) / 2.
      EXPECT_NEAR(state.slip_rate_m_s, -accel * 20 * kDt, 1e-12);
      EXPECT_NEAR(state.slip_m, -0.5 * accel * (20 * kDt) * (20 * kDt), accel * 20 * kDt * kDt);
    }
  }
  EXPECT_EQ(state.mode, GraspMode::kDropped);
  const double drop_time = std::sqrt(2 * 0.010 / accel);
  EXPECT_NEAR(steps * kDt, drop_time, 2 * kDt);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_FALSE(state.gripped);
  // Dropped: nothing afterwards, not even with the frame squeezing the empty space.
  forces = StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 2e-3), kDt);
  EXPECT_EQ(forces.grasp_force_n, 0.0);
  EXPECT_EQ(GraspServoLoad(scene, state).TorqueAt(1.5), 0.0);
}

TEST(GraspContactTest, SlidingObjectReSticksWhenTheGripTightens) {
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 3e-5), kDt);
  ASSERT_EQ(state.mode, GraspMode::kSliding);
  for (int i = 0; i < 5; ++i)
    StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 3e-5), kDt);
  const double slipped = state.slip_m;
  ASSERT_LT(slipped, 0.0);
  for (int i = 0; i < 50; ++i)
    StepGrasp(scene, state, HoverAt(1.0), AngleForOverlap(scene, 2e-3), kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
  EXPECT_EQ(state.slip_rate_m_s, 0.0);
  EXPECT_LT(state.slip_m, slipped);  // it kept sliding a little while decelerating
  EXPECT_GT(state.slip_m, -0.010);
}

TEST(GraspContactTest, PouredMassIsCarriedAsShear) {
  const GraspSceneParams scene = Scene();
  GraspState state = HeldState(scene);
  const double angle = AngleForOverlap(scene, 2e-3);
  PourMass(state, 0.180);
  PourMass(state, -1.0);
  PourMass(state, kNaN);
  EXPECT_NEAR(state.object_mass_kg, 0.230, 1e-15);
  const GraspForces forces = StepGrasp(scene, state, HoverAt(1.0), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
  EXPECT_NEAR(forces.shear_force_n, 0.230 * kG, 1e-12);
  EXPECT_NEAR(forces.payload_mass_kg, 0.230, 1e-15);
}

TEST(GraspContactTest, BalloonBurstsAndIsGone) {
  GraspSceneParams scene;
  scene.object = Balloon();
  scene.object.damage_mode = DamageMode::kBurst;
  scene.object.damage_force_n = 0.45;
  GraspState state = InitialGraspState(scene);
  const double angle = AngleForOverlap(scene, 1e-3);  // ~0.6 N per pad
  ASSERT_GT(SymmetricNormalForce(scene, state, angle), 0.45);
  StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  EXPECT_EQ(state.mode, GraspMode::kDestroyed);
  EXPECT_EQ(state.damage, DamageMode::kBurst);
  const GraspForces after = StepGrasp(scene, state, HoverAt(0.5), angle, kDt);
  EXPECT_EQ(after.grasp_force_n, 0.0);
  for (const Eigen::Vector3d& pad : after.pad_force_n) EXPECT_EQ(pad, Eigen::Vector3d::Zero());
  EXPECT_EQ(GraspServoLoad(scene, state).TorqueAt(angle), 0.0);
}

TEST(GraspContactTest, BalloonBelowTheLimitSurvives) {
  GraspSceneParams scene;
  scene.object = Balloon();
  scene.object.damage_mode = DamageMode::kBurst;
  scene.object.damage_force_n = 0.45;
  GraspState state = InitialGraspState(scene);
  StepGrasp(scene, state, HoverAt(0.5), AngleForOverlap(scene, 3e-4), kDt);  // ~0.19 N
  EXPECT_EQ(state.mode, GraspMode::kOnStand);
  EXPECT_EQ(state.damage, DamageMode::kNone);
}

TEST(GraspContactTest, CrackedEggIsRecordedAndStaysHeld) {
  GraspSceneParams scene;
  scene.object.mass_kg = 0.060;
  scene.object.half_width_m = 0.022;
  scene.object.stiffness = 1.5e7;
  scene.object.exponent = 1.5;
  scene.object.damage_mode = DamageMode::kCrack;
  scene.object.damage_force_n = 25.0;
  GraspState state = HeldState(scene);
  const double angle = AngleForOverlap(scene, 5e-3);  // ~27 N per pad
  GraspForces forces = StepGrasp(scene, state, HoverAt(1.0), angle, kDt);
  EXPECT_EQ(state.damage, DamageMode::kCrack);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
  forces = StepGrasp(scene, state, HoverAt(1.0), angle, kDt);
  EXPECT_GT(forces.grasp_force_n, 6 * 25.0);
  EXPECT_NEAR(forces.shear_force_n, 0.060 * kG, 1e-12);
}

TEST(GraspContactTest, PeaksAreTracked) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  StepGrasp(scene, state, HoverAt(0.5), AngleForOverlap(scene, 2e-3), kDt);
  StepGrasp(scene, state, HoverAt(0.5), AngleForOverlap(scene, 1e-3), kDt);
  EXPECT_NEAR(state.peak_normal_force_n, LinearSeriesForce(2000.0, 2e-3), 1e-12);
  EXPECT_NEAR(state.peak_indentation_m, 2e-3 * kPadK / (2000.0 + kPadK), 1e-15);
}

TEST(GraspContactTest, ElasticEnergyOfTheSqueeze) {
  const GraspSceneParams scene = Scene();
  GraspState state = InitialGraspState(scene);
  const GraspForces forces =
      StepGrasp(scene, state, HoverAt(0.5), AngleForOverlap(scene, 2e-3), kDt);
  // Six series springs: F^2 / 2 (1 / k_pad + 1 / k_object) each; no shear yet.
  const double f = LinearSeriesForce(2000.0, 2e-3);
  EXPECT_NEAR(forces.elastic_energy_j, 6 * 0.5 * f * f * (1 / kPadK + 1 / 2000.0), 1e-15);
}

TEST(GraspContactTest, NonFiniteInputsGiveZeroForcesAndKeepTheMode) {
  const GraspSceneParams scene = Scene();
  const double angle = AngleForOverlap(scene, 2e-3);
  GraspVehicleSample bad_position = HoverAt(1.0);
  bad_position.position_m.z() = kNaN;
  GraspVehicleSample bad_force = HoverAt(1.0);
  bad_force.specific_force_body_m_s2.x() = std::numeric_limits<double>::infinity();
  GraspVehicleSample bad_attitude = HoverAt(1.0);
  bad_attitude.orientation.coeffs().setZero();
  for (const GraspVehicleSample& vehicle : {bad_position, bad_force, bad_attitude}) {
    GraspState state = HeldState(scene);
    const GraspForces forces = StepGrasp(scene, state, vehicle, angle, kDt);
    EXPECT_EQ(state.mode, GraspMode::kHeld);
    EXPECT_EQ(forces.grasp_force_n, 0.0);
    EXPECT_EQ(forces.payload_mass_kg, 0.0);
  }
  GraspState state = HeldState(scene);
  EXPECT_EQ(StepGrasp(scene, state, HoverAt(1.0), kNaN, kDt).grasp_force_n, 0.0);
  EXPECT_EQ(StepGrasp(scene, state, HoverAt(1.0), angle, kNaN).grasp_force_n, 0.0);
  EXPECT_EQ(state.mode, GraspMode::kHeld);
}

TEST(GraspContactTest, DefaultForcesAreZero) {
  const GraspForces forces;
  for (const Eigen::Vector3d& pad : forces.pad_force_n) EXPECT_EQ(pad, Eigen::Vector3d::Zero());
  for (double normal : forces.normal_force_n) EXPECT_EQ(normal, 0.0);
}

TEST(GraspContactTest, ModeNames) {
  EXPECT_STREQ(GraspModeName(GraspMode::kNoObject), "no_object");
  EXPECT_STREQ(GraspModeName(GraspMode::kOnStand), "on_stand");
  EXPECT_STREQ(GraspModeName(GraspMode::kHeld), "held");
  EXPECT_STREQ(GraspModeName(GraspMode::kSliding), "sliding");
  EXPECT_STREQ(GraspModeName(GraspMode::kDropped), "dropped");
  EXPECT_STREQ(GraspModeName(GraspMode::kDestroyed), "destroyed");
}

}  // namespace
}  // namespace hilrig::host
