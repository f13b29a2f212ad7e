// The grasp parts of a spec: objects, grasp commands, pours, hand-overs and the signals that watch
// them are checked before anything runs, each problem pointing at its field.
#include "host/scenario/scenario_validation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

constexpr const char* kGraspScene = R"(name: "grasp"
vehicle { initial_position_m { z: 0.5 } }
models { tactile { enabled: true } }
object { fixture: "balloon" }
simulation { duration_s: 10 }
timeline { at_s: 1 grasp { force_n: 0.6 } }
envelopes { name: "force" signal: GRASP_FORCE_N upper: 0.65 }
)";

std::string ErrorOf(const std::string& text) {
  const auto result = ParseScenario(text, "spec.textproto");
  EXPECT_FALSE(result.ok()) << "expected an error for:\n" << text;
  return result.ok() ? std::string() : result.error().message;
}

TEST(ScenarioValidationTest, AcceptsAGraspScene) {
  const auto result = ParseScenario(kGraspScene, "spec.textproto");
  EXPECT_TRUE(result.ok()) << result.error().message;
}

TEST(ScenarioValidationTest, EveryShippedScenarioIsValid) {
  for (const char* name : {"balloon_grasp", "balloon_ablation", "load_ramp", "bottle_feedback",
                           "bottle_ablation", "objects"}) {
    const auto result =
        LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/" + name + ".textproto");
    EXPECT_TRUE(result.ok()) << name << ": " << result.error().message;
  }
}

TEST(ScenarioValidationTest, UnknownFixtureListsTheKnownOnes) {
  std::string spec = kGraspScene;
  spec.replace(spec.find("\"balloon\""), 9, "\"vase\"");
  const std::string error = ErrorOf(spec);
  EXPECT_THAT(error, HasSubstr("object.fixture"));
  EXPECT_THAT(error, HasSubstr("balloon"));
  EXPECT_THAT(error, HasSubstr("glass_cup"));
}

TEST(ScenarioValidationTest, StiffnessScaleMustBePositive) {
  std::string spec = kGraspScene;
  spec.replace(spec.find("fixture: \"balloon\""), 18, "fixture: \"balloon\" stiffness_scale: 0");
  const std::string error = ErrorOf(spec);
  EXPECT_THAT(error, HasSubstr("object.stiffness_scale: must be > 0"));
}

TEST(ScenarioValidationTest, GraspWithoutAnObjectIsRejected) {
  const std::string error = ErrorOf(R"(name: "x"
models { tactile { enabled: true } }
simulation { duration_s: 2 }
timeline { at_s: 1 grasp { force_n: 0.6 } }
)");
  EXPECT_THAT(error,
              HasSubstr("timeline[0].grasp: commands the gripper, but the scene has no object"));
}

TEST(ScenarioValidationTest, RegulatingGraspNeedsTheTactilePads) {
  const std::string error = ErrorOf(R"(name: "x"
object { fixture: "egg" }
simulation { duration_s: 2 }
timeline { at_s: 1 grasp { force_n: 2 } }
)");
  EXPECT_THAT(error, HasSubstr("needs models.tactile.enabled"));
}

// The default servo (0.25 N m at stall, pads moving 25 mm per radian) squeezes at most 10 N; a
// stronger servo allows more.
TEST(ScenarioValidationTest, GraspForceBeyondWhatTheServoCanHoldIsRefused) {
  const std::string error =
      ErrorOf(std::string(kGraspScene) + "timeline { at_s: 2 grasp { force_n: 19 } }\n");
  EXPECT_THAT(error, HasSubstr("timeline[1].grasp.force_n: must be in (0, 10] N: at its stall "
                               "torque the servo squeezes at most that over the six pads"));
  EXPECT_TRUE(
      ParseScenario(std::string(kGraspScene) + "timeline { at_s: 2 grasp { force_n: 10 } }\n",
                    "spec.textproto")
          .ok());
  std::string stronger = std::string(kGraspScene) + "timeline { at_s: 2 grasp { force_n: 19 } }\n";
  stronger.replace(stronger.find("tactile { enabled: true }"), 25,
                   "tactile { enabled: true } gripper { stall_torque_nm: 0.5 }");
  EXPECT_TRUE(ParseScenario(stronger, "spec.textproto").ok()) << ErrorOf(stronger);
}

TEST(ScenarioValidationTest, AnObjectsOwnDamageForceMustBePositive) {
  std::string spec = kGraspScene;
  spec.replace(spec.find("fixture: \"balloon\""), 18, "fixture: \"balloon\" damage_force_n: 0");
  EXPECT_THAT(ErrorOf(spec), HasSubstr("object.damage_force_n: must be > 0"));
}

TEST(ScenarioValidationTest, GraspNeedsAForceOrOpen) {
  const std::string error = ErrorOf(std::string(kGraspScene) + "timeline { at_s: 2 grasp { } }\n");
  EXPECT_THAT(error, HasSubstr("force_n is required (or open: true)"));
}

TEST(ScenarioValidationTest, PourNeedsAPositiveMassAndDuration) {
  const std::string error =
      ErrorOf(std::string(kGraspScene) + "timeline { at_s: 2 pour { mass_kg: -1 } }\n");
  EXPECT_THAT(error, HasSubstr("timeline[1].pour.mass_kg: must be > 0"));
  EXPECT_THAT(error, HasSubstr("timeline[1].pour: duration_s is required"));
}

TEST(ScenarioValidationTest, GraspSignalNeedsAnObject) {
  const std::string error = ErrorOf(R"(name: "x"
simulation { duration_s: 2 }
envelopes { name: "d" signal: OBJECT_DAMAGED upper: 0 }
)");
  EXPECT_THAT(error,
              HasSubstr("envelopes[0].signal: watches the grasp, but the scene has no object"));
}

TEST(ScenarioValidationTest, HeldAndSlipSignalsNeedAnObject) {
  const std::string error = ErrorOf(R"(name: "x"
simulation { duration_s: 2 }
envelopes { name: "h" signal: OBJECT_HELD lower: 1 }
envelopes { name: "s" signal: SLIP_SPEED_M_S upper: 0.01 }
)");
  EXPECT_THAT(error, HasSubstr("envelopes[0].signal: watches the grasp"));
  EXPECT_THAT(error, HasSubstr("envelopes[1].signal: watches the grasp"));
}

TEST(ScenarioValidationTest, APadSignalNeedsAPadOfTheSix) {
  const std::string scene = std::string(kGraspScene);
  EXPECT_THAT(ErrorOf(scene + "envelopes { name: \"p\" signal: PAD_FORCE_N upper: 1 }\n"),
              HasSubstr("envelopes[1]: signal PAD_FORCE_N needs pad: the tactile pad it watches, "
                        "0 to 5"));
  EXPECT_THAT(
      ErrorOf(scene + "envelopes { name: \"p\" signal: PAD_FORCE_ESTIMATE_N pad: 6 upper: 1 }\n"),
      HasSubstr("envelopes[1].pad: must be 0 to 5 (six pads), got 6"));
  EXPECT_THAT(ErrorOf(scene + "envelopes { name: \"p\" signal: GRASP_FORCE_N pad: 1 upper: 1 }\n"),
              HasSubstr("envelopes[1].pad: only a PAD_* signal watches one pad; GRASP_FORCE_N "
                        "does not"));
  const auto fine = ParseScenario(
      scene + "envelopes { name: \"p\" signal: PAD_FORCE_ERROR_N pad: 5 upper: 1 }\n", "spec");
  EXPECT_TRUE(fine.ok()) << fine.error().message;
}

TEST(ScenarioValidationTest, ControllerGainsMustBePositive) {
  const std::string error =
      ErrorOf(std::string(kGraspScene) + "grasp_controller { damping: -3 mass: 0 }\n");
  EXPECT_THAT(error, HasSubstr("grasp_controller.damping: must be > 0"));
  EXPECT_THAT(error, HasSubstr("grasp_controller.mass: must be > 0"));
}

TEST(ScenarioValidationTest, MeanWindowMustBePositive) {
  const std::string error =
      ErrorOf(std::string(kGraspScene) +
              "envelopes { name: \"m\" signal: GRASP_FORCE_N upper: 1 mean_over_s: -1 }\n");
  EXPECT_THAT(error, HasSubstr("envelopes[1].mean_over_s: must be > 0"));
}

// 1e300 s once became one sample (lround out of range) and 2^32 s a window cut modulo 2^32
// samples: a run that zeroed in a way the spec never asked for. No run outlasts a day.
TEST(ScenarioValidationTest, ZeroingWindowLongerThanAnyRunIsRejected) {
  for (const char* zeroing : {"1e300", "4294967296", "86401"}) {
    std::string spec = kGraspScene;
    spec.replace(spec.find("enabled: true"), 13,
                 std::string("enabled: true zeroing_s: ") + zeroing);
    EXPECT_THAT(ErrorOf(spec), HasSubstr("models.tactile.zeroing_s: must be at most 86400 s"))
        << zeroing;
  }
  std::string longest = kGraspScene;
  longest.replace(longest.find("enabled: true"), 13, "enabled: true zeroing_s: 86400");
  EXPECT_TRUE(ParseScenario(longest, "spec.textproto").ok());
}

// The DUT keeps at most 16 forces per pad; 0 would be no force at all.
TEST(ScenarioValidationTest, ForceAverageOutsideWhatTheDutKeepsIsRejected) {
  for (const char* samples : {"0", "17"}) {
    std::string spec = kGraspScene;
    spec.replace(spec.find("enabled: true"), 13,
                 std::string("enabled: true force_average_samples: ") + samples);
    EXPECT_THAT(ErrorOf(spec),
                HasSubstr("models.tactile.force_average_samples: must lie in [1, 16]"))
        << samples;
  }
  for (const char* samples : {"1", "16"}) {
    std::string spec = kGraspScene;
    spec.replace(spec.find("enabled: true"), 13,
                 std::string("enabled: true force_average_samples: ") + samples);
    const auto parsed = ParseScenario(spec, "spec.textproto");
    ASSERT_TRUE(parsed.ok()) << samples;
    EXPECT_EQ(ResolveScenario(parsed.value(), std::nullopt).hall_sensors.force_average_samples,
              std::stoul(samples));
  }
  const auto defaulted = ParseScenario(kGraspScene, "spec.textproto");
  ASSERT_TRUE(defaulted.ok());
  EXPECT_EQ(ResolveScenario(defaulted.value(), std::nullopt).hall_sensors.force_average_samples,
            kDefaultForceAverageSamples);
}

TEST(ScenarioValidationTest, PositionsFarFromTheBenchAreRejected) {
  std::string far_start = kGraspScene;
  far_start.replace(far_start.find("z: 0.5"), 6, "z: 1e300");
  EXPECT_THAT(ErrorOf(far_start),
              HasSubstr("vehicle.initial_position_m.z: must be within 1000 m of the origin"));
  const std::string far_setpoint =
      std::string(kGraspScene) + "timeline { at_s: 2 setpoint { position_m { x: -1000.5 } } }\n";
  EXPECT_THAT(ErrorOf(far_setpoint),
              HasSubstr("timeline[1].setpoint.position_m.x: must be within 1000 m of the origin"));
  const std::string edge =
      std::string(kGraspScene) + "timeline { at_s: 2 setpoint { position_m { y: 1000 } } }\n";
  EXPECT_TRUE(ParseScenario(edge, "spec.textproto").ok());
}

TEST(ScenarioValidationTest, AnImuFullScaleMustBePositive) {
  std::string spec = kGraspScene;
  spec.replace(spec.find("models {"), 8,
               "models {\n  imu { accel_range_m_s2: 0 gyro_range_rad_s: -1 }");
  const std::string error = ErrorOf(spec);
  EXPECT_THAT(error, HasSubstr("models.imu.accel_range_m_s2: must be > 0"));
  EXPECT_THAT(error, HasSubstr("models.imu.gyro_range_rad_s: must be > 0"));
}

TEST(ScenarioValidationTest, AGeodeticOriginOffTheModelsRangeIsNamed) {
  std::string spec = kGraspScene;
  spec +=
      "environment { geodetic_origin { latitude_deg: 90 longitude_deg: 200 altitude_m: 9000 } }";
  const std::string error = ErrorOf(spec);
  EXPECT_THAT(error,
              HasSubstr("environment.geodetic_origin.latitude_deg: must be within -85 .. 85"));
  EXPECT_THAT(error, HasSubstr("environment.geodetic_origin.longitude_deg"));
  EXPECT_THAT(error, HasSubstr("environment.geodetic_origin.altitude_m"));
  spec = kGraspScene;
  spec += "environment { geodetic_origin { latitude_deg: 52.31 longitude_deg: 4.77 } }";
  EXPECT_TRUE(ParseScenario(spec, "spec.textproto").ok());
}

TEST(ScenarioValidationTest, HandOverWithoutAnObjectIsRejected) {
  const std::string error = ErrorOf(R"(name: "x"
simulation { duration_s: 2 }
timeline { at_s: 1 remove_support { } }
)");
  EXPECT_THAT(error, HasSubstr("timeline[0].remove_support"));
}

}  // namespace
}  // namespace hilrig::host
