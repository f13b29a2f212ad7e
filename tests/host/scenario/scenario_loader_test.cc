#include "host/scenario/scenario_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

constexpr const char* kMinimal = R"(name: "minimal"
simulation { duration_s: 1 }
envelopes { name: "alt" signal: ALTITUDE_M upper: 2 }
)";

std::string ErrorOf(const std::string& text) {
  const auto result = ParseScenario(text, "spec.textproto");
  EXPECT_FALSE(result.ok()) << "expected an error for:\n" << text;
  return result.ok() ? std::string() : result.error().message;
}

TEST(ScenarioLoaderTest, AcceptsMinimalSpec) {
  const auto result = ParseScenario(kMinimal, "spec.textproto");
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result.value().name(), "minimal");
}

TEST(ScenarioLoaderTest, LoadsShippedHoverScenario) {
  const auto result =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/hover.textproto");
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_GE(result.value().envelopes_size(), 2);
}

TEST(ScenarioLoaderTest, SyntaxErrorNamesLineAndColumn) {
  const std::string error = ErrorOf("name: \"x\"\nsimulation { duration_s: 1 \n");
  EXPECT_THAT(error, HasSubstr("spec.textproto:3:1"));
}

TEST(ScenarioLoaderTest, UnknownFieldIsNamedWithItsLocation) {
  const std::string error = ErrorOf("name: \"x\"\nvehicle {\n  mas_kg: 1\n}\n");
  EXPECT_THAT(error, HasSubstr("spec.textproto:3:"));
  EXPECT_THAT(error, HasSubstr("mas_kg"));
}

TEST(ScenarioLoaderTest, NegativeMassPointsAtTheField) {
  const std::string error = ErrorOf(std::string(kMinimal) + "vehicle {\n  mass_kg: -0.5\n}\n");
  EXPECT_THAT(error, HasSubstr("spec.textproto:5:3: vehicle.mass_kg: must be > 0"));
}

TEST(ScenarioLoaderTest, EnvelopeWithoutLimitPointsAtTheEnvelope) {
  const std::string error = ErrorOf(
      "name: \"x\"\nsimulation { duration_s: 1 }\nenvelopes { name: \"e\" signal: TILT_DEG }\n");
  EXPECT_THAT(error, HasSubstr("spec.textproto:3:1: envelopes[0]: needs a limit"));
}

TEST(ScenarioLoaderTest, NonFiniteNumberIsRejected) {
  const std::string error = ErrorOf(std::string(kMinimal) + "vehicle { arm_length_m: nan }\n");
  EXPECT_THAT(error, HasSubstr("vehicle.arm_length_m: must be a finite number"));
}

TEST(ScenarioLoaderTest, MissingDurationIsReported) {
  const std::string error = ErrorOf("name: \"x\"\nsimulation { physics_rate_hz: 1000 }\n");
  EXPECT_THAT(error, HasSubstr("simulation: duration_s is required"));
}

TEST(ScenarioLoaderTest, ControlRateMustDividePhysicsRate) {
  const std::string error =
      ErrorOf("name: \"x\"\nsimulation { duration_s: 1 control_rate_hz: 300 }\n");
  EXPECT_THAT(error, HasSubstr("simulation.control_rate_hz: must divide physics_rate_hz"));
}

// 1000 / 1e-300 is a whole number to a double, so 1e-300 Hz once "divided" the physics rate and
// the run died on a division by zero.
TEST(ScenarioLoaderTest, RatesTooSlowToCountInTicksAreRejected) {
  for (const char* field : {"control_rate_hz", "trace_rate_hz"}) {
    const std::string error =
        ErrorOf(std::string("name: \"x\"\nsimulation { duration_s: 1 ") + field + ": 1e-300 }\n");
    EXPECT_THAT(error,
                HasSubstr(std::string("simulation.") + field + ": must be at least 0.01 Hz"));
  }
  EXPECT_TRUE(
      ParseScenario("name: \"x\"\nsimulation { duration_s: 1 trace_rate_hz: 0.01 }\n", "s").ok());
}

// The VIO's period at 1e300 Hz rounded to 0 ns and the run died dividing by it; at 1e-300 Hz it
// overflowed. Both emulators sample on the physics ticks.
TEST(ScenarioLoaderTest, SensorRatesMustFitTheTicks) {
  for (const char* sensor : {"imu", "vio"}) {
    for (const char* rate : {"1e300", "1001", "1e-300"}) {
      const std::string error =
          ErrorOf(std::string("name: \"x\"\nsimulation { duration_s: 1 }\nmodels { ") + sensor +
                  " { rate_hz: " + rate + " } }\n");
      EXPECT_THAT(error, HasSubstr(std::string("models.") + sensor +
                                   ".rate_hz: must be in [0.01 Hz, physics_rate_hz (1000"))
          << sensor << " " << rate;
    }
  }
  EXPECT_TRUE(ParseScenario("name: \"x\"\nsimulation { duration_s: 1 physics_rate_hz: 2000 }\n"
                            "models { imu { rate_hz: 2000 } vio { rate_hz: 0.01 } }\n",
                            "s")
                  .ok());
}

// 1 kHz nodes in a 500 Hz scene sent 500 samples a second each, and the DUT counted every other
// one as lost on the bus; the default 50 Hz nodes cannot run in a 20 Hz scene either.
TEST(ScenarioLoaderTest, NodeRateAboveTheTickRateIsRefused) {
  EXPECT_THAT(ErrorOf("name: \"x\"\nsimulation { duration_s: 1 physics_rate_hz: 500 }\n"
                      "models { tactile { enabled: true node_rate_hz: 1000 } }\n"),
              HasSubstr("models.tactile.node_rate_hz: the nodes sample on physics ticks: 1000 Hz "
                        "is above physics_rate_hz (500 Hz)"));
  EXPECT_THAT(ErrorOf("name: \"x\"\nsimulation { duration_s: 1 physics_rate_hz: 20 }\n"
                      "models { tactile { enabled: true } }\n"),
              HasSubstr("50 Hz is above physics_rate_hz (20 Hz)"));
  EXPECT_TRUE(ParseScenario("name: \"x\"\nsimulation { duration_s: 1 physics_rate_hz: 500 }\n"
                            "models { tactile { enabled: true node_rate_hz: 500 } }\n",
                            "s")
                  .ok());
}

TEST(ScenarioLoaderTest, ReportsEveryProblemAtOnce) {
  const std::string error = ErrorOf(
      "name: \"x\"\nsimulation { duration_s: -1 }\nvehicle { mass_kg: 0 arm_length_m: -1 }\n");
  EXPECT_THAT(error, HasSubstr("simulation.duration_s"));
  EXPECT_THAT(error, HasSubstr("vehicle.mass_kg"));
  EXPECT_THAT(error, HasSubstr("vehicle.arm_length_m"));
}

TEST(ScenarioLoaderTest, TimelineOutsideTheRunIsRejected) {
  const std::string error =
      ErrorOf(std::string(kMinimal) + "timeline { at_s: 5 setpoint { position_m { z: 1 } } }\n");
  EXPECT_THAT(error, HasSubstr("timeline[0].at_s: must lie inside the run"));
}

TEST(ScenarioLoaderTest, DuplicateEnvelopeNamesAreRejected) {
  const std::string error =
      ErrorOf(std::string(kMinimal) + "envelopes { name: \"alt\" signal: TILT_DEG upper: 1 }\n");
  EXPECT_THAT(error, HasSubstr("envelopes[1].name"));
}

TEST(ScenarioLoaderTest, VehicleThatCannotLiftItselfIsRejected) {
  const std::string error =
      ErrorOf(std::string(kMinimal) + "vehicle { mass_kg: 2 max_thrust_per_rotor_n: 1 }\n");
  EXPECT_THAT(error, HasSubstr("cannot lift"));
}

TEST(ScenarioLoaderTest, TactileEnvelopeNeedsTheTactilePads) {
  const std::string error = ErrorOf(
      std::string(kMinimal) + "envelopes { name: \"pads\" signal: TACTILE_FORCE_N upper: 1 }\n");
  EXPECT_THAT(error, HasSubstr("envelopes[1].signal: watches the tactile pads"));
}

TEST(ScenarioLoaderTest, UnknownFieldFidelityIsRejected) {
  const std::string error =
      ErrorOf(std::string(kMinimal) + "models { tactile { field_fidelity: \"tiles:999\" } }\n");
  EXPECT_THAT(error, HasSubstr("models.tactile.field_fidelity"));
}

TEST(ScenarioLoaderTest, MissingFileIsAnErrorNamingTheFile) {
  const auto result = LoadScenario("/nonexistent/dir/none.textproto");
  ASSERT_FALSE(result.ok());
  EXPECT_THAT(result.error().message, HasSubstr("/nonexistent/dir/none.textproto"));
  EXPECT_THAT(result.error().message, HasSubstr("cannot read"));
  EXPECT_THAT(result.error().message, HasSubstr("No such file or directory"));
}

}  // namespace
}  // namespace hilrig::host
