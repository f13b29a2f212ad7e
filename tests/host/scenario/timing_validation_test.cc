// The real-time timing envelopes of a spec (`timing { ... }`): every field is checked before a run,
// each problem pointing at its file:line:column and field, and the late threshold resolves to one
// physics period unless the spec sets it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/scenario/scenario_validation.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

std::string SceneWithTiming(const std::string& timing) {
  return "name: \"rt\"\nsimulation { duration_s: 1 physics_rate_hz: 500 }\ntiming { " + timing +
         " }\n";
}

std::string ErrorOf(const std::string& text) {
  const auto result = ParseScenario(text, "spec.textproto");
  EXPECT_FALSE(result.ok()) << "expected an error for:\n" << text;
  return result.ok() ? std::string() : result.error().message;
}

TEST(TimingValidationTest, AcceptsLooseEnvelopes) {
  const auto result = ParseScenario(
      SceneWithTiming("late_threshold_s: 0.002 loop_period_p99_max_s: 0.004 loop_period_max_s: "
                      "0.05 late_tick_fraction_max: 0.05 dut_latency_p99_max_s: 0.005 "
                      "dut_commands_missed_fraction_max: 0"),
      "spec.textproto");
  EXPECT_TRUE(result.ok()) << result.error().message;
}

TEST(TimingValidationTest, ErrorNamesFileLineColumnAndField) {
  const std::string error = ErrorOf(SceneWithTiming("loop_period_max_s: -0.01"));
  EXPECT_THAT(error, HasSubstr("spec.textproto:3:10: timing.loop_period_max_s: must be > 0"));
}

TEST(TimingValidationTest, NonFiniteLimitsAreRejected) {
  for (const char* value : {"nan", "inf", "-inf"}) {
    const std::string error =
        ErrorOf(SceneWithTiming(std::string("dut_latency_p99_max_s: ") + value));
    EXPECT_THAT(error, HasSubstr("timing.dut_latency_p99_max_s: must be a finite number")) << value;
  }
}

// At 500 Hz the period is 2 ms: a p99 limit of 1.5 ms could never be met.
TEST(TimingValidationTest, PeriodLimitsBelowThePhysicsPeriodAreRejected) {
  const std::string error = ErrorOf(SceneWithTiming("loop_period_p99_max_s: 0.0015"));
  EXPECT_THAT(error, HasSubstr("timing.loop_period_p99_max_s: must be >= the physics period"));
}

TEST(TimingValidationTest, FractionsMustLieInZeroToOne) {
  EXPECT_THAT(ErrorOf(SceneWithTiming("late_tick_fraction_max: 1.5")),
              HasSubstr("timing.late_tick_fraction_max: must be a fraction in [0, 1]"));
  EXPECT_THAT(ErrorOf(SceneWithTiming("dut_commands_missed_fraction_max: -0.1")),
              HasSubstr("timing.dut_commands_missed_fraction_max: must be a fraction in [0, 1]"));
}

TEST(TimingValidationTest, LateThresholdMustBePositiveAndUnderASecond) {
  EXPECT_THAT(ErrorOf(SceneWithTiming("late_threshold_s: 0")),
              HasSubstr("timing.late_threshold_s: must be in (0, 1) s"));
  EXPECT_THAT(ErrorOf(SceneWithTiming("late_threshold_s: 2")),
              HasSubstr("timing.late_threshold_s: must be in (0, 1) s"));
}

TEST(TimingValidationTest, LateThresholdDefaultsToOnePhysicsPeriod) {
  const auto spec = ParseScenario(SceneWithTiming(""), "spec.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;

  const ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);

  EXPECT_EQ(config.late_threshold_ns, 2'000'000);
}

TEST(TimingValidationTest, LateThresholdFromTheSpec) {
  const auto spec = ParseScenario(SceneWithTiming("late_threshold_s: 0.0005"), "spec.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;

  const ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);

  EXPECT_EQ(config.late_threshold_ns, 500'000);
}

TEST(TimingValidationTest, LimitsResolveToWhatTheSpecSets) {
  const auto spec = ParseScenario(
      SceneWithTiming("loop_period_max_s: 0.05 dut_commands_missed_fraction_max: 0.1"),
      "spec.textproto");
  ASSERT_TRUE(spec.ok()) << spec.error().message;

  const TimingLimits limits = ResolveScenario(spec.value(), std::nullopt).timing;

  EXPECT_EQ(limits.loop_period_max_s, 0.05);
  EXPECT_EQ(limits.dut_commands_missed_fraction_max, 0.1);
  EXPECT_FALSE(limits.loop_period_p99_max_s.has_value());
  EXPECT_FALSE(limits.late_tick_fraction_max.has_value());
  EXPECT_FALSE(limits.dut_latency_p99_max_s.has_value());
}

TEST(TimingValidationTest, TheBenchScenarioIsValid) {
  const auto result =
      LoadScenario(::hilrig::test_support::SourceDir() + "/scenarios/bench/realtime_60s.textproto");
  EXPECT_TRUE(result.ok()) << result.error().message;
}

}  // namespace
}  // namespace hilrig::host
