// The gripper's sequencing of the timeline: grasp commands, objects put on the stand, pours and the
// stand taken away; and the contact force summed from the pads as the DUT would see it.
#include "host/runner/gripper_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

constexpr double kDt = 1e-3;

ScenarioConfig ConfigFrom(const std::string& timeline) {
  const auto spec = ParseScenario(R"(name: "g"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true } }
object { fixture: "bead_container" }
simulation { duration_s: 20 }
)" + timeline,
                                  "g.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), std::nullopt);
}

// Steps the scene with the vehicle hovering still at 0.5 m and the servo commanded to `angle_rad`.
void StepFor(GripperScene& scene, const ScenarioConfig& config, double from_s, double to_s,
             double angle_rad) {
  const QuadrotorState hover =
      MakeHoveringQuadrotor(config.vehicle, Eigen::Vector3d(0, 0, 0.5), 0.0);
  // Whole ticks, as the runner's clock gives them (summing dt would drift over a pour's window).
  for (long tick = std::lround(from_s / kDt); tick < std::lround(to_s / kDt); ++tick) {
    scene.Step(static_cast<double>(tick) * kDt, angle_rad, hover, kDt);
  }
}

// Servo angle that squeezes the 35 mm container by 1 mm.
double SqueezeAngle(const ScenarioConfig& config) {
  return AngleForPadRadius(config.gripper.frame, 0.035 - 0.001);
}

TEST(GripperSceneTest, CommandIsTheLatestGraspWithTheReferenceJustBeforeTheObject) {
  const ScenarioConfig config = ConfigFrom(R"(
timeline { at_s: 1 grasp { force_n: 2 } }
timeline { at_s: 3 grasp { open: true } }
timeline { at_s: 5 grasp { force_n: 1 reference_angle_rad: 0.7 } }
)");
  GripperScene scene(config, config.hall_sensors.tactile);
  EXPECT_FALSE(scene.CommandAt(0.5).regulate);
  const GripperCommand grasp = scene.CommandAt(2.0);
  EXPECT_TRUE(grasp.regulate);
  EXPECT_EQ(grasp.force_n, 2.0);
  // Half a millimetre before the 35 mm surface: (55 - 35.5) mm / 25 mm/rad.
  EXPECT_NEAR(grasp.reference_angle_rad, 0.78, 1e-12);
  EXPECT_FALSE(scene.CommandAt(4.0).regulate);
  EXPECT_EQ(scene.CommandAt(6.0).reference_angle_rad, 0.7);
}

TEST(GripperSceneTest, PourAddsItsMassAtAConstantRateOverItsWindow) {
  const ScenarioConfig config =
      ConfigFrom("timeline { at_s: 1 pour { mass_kg: 0.1 duration_s: 2 } }\n");
  GripperScene scene(config, config.hall_sensors.tactile);
  StepFor(scene, config, 0.0, 2.0, 0.0);
  EXPECT_NEAR(scene.grasp().object_mass_kg, 0.061 + 0.05, 1e-9);
  StepFor(scene, config, 2.0, 5.0, 0.0);
  EXPECT_NEAR(scene.grasp().object_mass_kg, 0.061 + 0.1, 1e-9);
}

TEST(GripperSceneTest, TakingTheStandAwayHangsTheObjectOnThePads) {
  const ScenarioConfig config = ConfigFrom("timeline { at_s: 1 remove_support { } }\n");
  GripperScene scene(config, config.hall_sensors.tactile);
  StepFor(scene, config, 0.0, 0.9, SqueezeAngle(config));
  EXPECT_EQ(scene.grasp().mode, GraspMode::kOnStand);
  StepFor(scene, config, 0.9, 1.5, SqueezeAngle(config));
  EXPECT_EQ(scene.grasp().mode, GraspMode::kHeld);
  EXPECT_NEAR(scene.forces().payload_mass_kg, 0.061, 1e-12);
}

// What ideal pads would tell the DUT about a held object in hover: its weight, straight down.
TEST(GripperSceneTest, ContactForceOfAHeldObjectIsItsWeight) {
  const ScenarioConfig config = ConfigFrom("timeline { at_s: 0.5 remove_support { } }\n");
  GripperScene scene(config, config.hall_sensors.tactile);
  StepFor(scene, config, 0.0, 1.0, SqueezeAngle(config));
  const Eigen::Vector3d force_n = scene.ContactForceWorld(Eigen::Quaterniond::Identity());
  EXPECT_NEAR(force_n.z(), -0.061 * config.vehicle.gravity_m_s2, 1e-9);
  EXPECT_NEAR(force_n.head<2>().norm(), 0.0, 1e-9);
}

// A crash-like sideways spike (30 g, as a touch-down gives for a tick): 0.061 kg x 300 m/s^2 / 3 =
// 6.1 N is more than the pads on the push side press with (0.9 N each where the servo settles), so
// they let go, the others carry the whole push, and the scene counts the tick.
TEST(GripperSceneTest, PadsReleasedByASidewaysPushAreCountedAndTheRestCarryIt) {
  const ScenarioConfig config = ConfigFrom("timeline { at_s: 0.5 remove_support { } }\n");
  GripperScene scene(config, config.hall_sensors.tactile);
  StepFor(scene, config, 0.0, 1.0, SqueezeAngle(config));
  ASSERT_EQ(scene.grasp().mode, GraspMode::kHeld);
  EXPECT_EQ(scene.pad_release_ticks(), 0u);

  QuadrotorState pushed = MakeHoveringQuadrotor(config.vehicle, Eigen::Vector3d(0, 0, 0.5), 0.0);
  pushed.specific_force_body_m_s2 = {300.0, 0.0, config.vehicle.gravity_m_s2};
  scene.Step(1.0, SqueezeAngle(config), pushed, kDt);

  ASSERT_EQ(scene.grasp().mode, GraspMode::kHeld);
  EXPECT_EQ(scene.forces().released_pads, 2);
  EXPECT_EQ(scene.pad_release_ticks(), 1u);
  EXPECT_LT(scene.unbalanced_horizontal_max_n(), 1e-12);
  // The object pushes back on the vehicle with exactly m a through the pads still touching it.
  const Eigen::Vector3d force_n = scene.ContactForceWorld(Eigen::Quaterniond::Identity());
  EXPECT_NEAR(force_n.x(), -0.061 * 300.0, 1e-9);
  EXPECT_NEAR(force_n.y(), 0.0, 1e-9);
}

TEST(GripperSceneTest, PresentingTheNextObjectKeepsTheFirstOnesOutcome) {
  const ScenarioConfig config = ConfigFrom(R"(
timeline { at_s: 1 present_object { fixture: "egg" } }
)");
  GripperScene scene(config, config.hall_sensors.tactile);
  StepFor(scene, config, 0.0, 2.0, 0.0);
  const auto outcomes = scene.Outcomes();
  ASSERT_EQ(outcomes.size(), 2u);
  EXPECT_EQ(outcomes[0].fixture(), "bead_container");
  EXPECT_EQ(outcomes[0].final_state(), "on_stand");
  EXPECT_EQ(outcomes[1].fixture(), "egg");
  EXPECT_EQ(scene.scene().object.half_width_m, 0.022);
}

TEST(GripperSceneTest, EnergyBoundIsTheServosWorkOverItsRange) {
  const ScenarioConfig config = ConfigFrom("");
  const GripperScene scene(config, config.hall_sensors.tactile);
  EXPECT_NEAR(scene.elastic_energy_bound_j(), 0.25 * 1.6, 1e-12);
}

}  // namespace
}  // namespace hilrig::host
