// Grading a run's timing against the spec's timing envelopes: real-time figures against their
// limits, lockstep runs and unmeasured DUT latency listed as not evaluated.
#include "host/runner/timing_checks.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

proto::Timing RealtimeFigures() {
  proto::Timing timing;
  timing.set_mode("realtime");
  timing.set_ticks(1000);
  timing.set_loop_period_p99_s(0.0012);
  timing.set_loop_period_max_s(0.030);
  timing.set_late_ticks(20);
  timing.set_control_ticks(1000);
  timing.set_dut_commands_missed(100);
  return timing;
}

proto::StreamLatency Stream(const std::string& name, double p99_s, std::uint64_t count = 10) {
  proto::StreamLatency stream;
  stream.set_stream(name);
  stream.set_count(count);
  stream.set_p99_s(p99_s);
  return stream;
}

TEST(TimingChecksTest, OnlyTheLimitsTheSpecSetsAreGraded) {
  TimingLimits limits;
  limits.loop_period_max_s = 0.05;

  const auto results = GradeTiming(limits, RealtimeFigures());

  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].name(), "loop_period_max_s");
  EXPECT_TRUE(results[0].evaluated());
  EXPECT_TRUE(results[0].passed());
  EXPECT_DOUBLE_EQ(results[0].value(), 0.030);
  EXPECT_DOUBLE_EQ(results[0].limit(), 0.05);
}

TEST(TimingChecksTest, AFigureOverItsLimitFails) {
  TimingLimits limits;
  limits.loop_period_p99_max_s = 0.001;

  const auto results = GradeTiming(limits, RealtimeFigures());

  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].passed());
  EXPECT_DOUBLE_EQ(results[0].value(), 0.0012);
}

TEST(TimingChecksTest, FractionsAreCountsOverTicks) {
  TimingLimits limits;
  limits.late_tick_fraction_max = 0.05;
  limits.dut_commands_missed_fraction_max = 0.05;

  const auto results = GradeTiming(limits, RealtimeFigures());

  ASSERT_EQ(results.size(), 2u);
  EXPECT_DOUBLE_EQ(results[0].value(), 0.02);  // 20 late of 1000
  EXPECT_TRUE(results[0].passed());
  EXPECT_DOUBLE_EQ(results[1].value(), 0.1);  // 100 missed of 1000
  EXPECT_FALSE(results[1].passed());
}

TEST(TimingChecksTest, DutLatencyIsTheSlowestStreamsP99) {
  TimingLimits limits;
  limits.dut_latency_p99_max_s = 0.005;
  proto::Timing timing = RealtimeFigures();
  *timing.add_dut_latency() = Stream("imu", 0.0004);
  *timing.add_dut_latency() = Stream("vio", 0.0061);
  *timing.add_dut_latency() = Stream("can", 0.0009);
  *timing.add_dut_latency() = Stream("setpoint", 0.5, 0);  // no samples: ignored

  const auto results = GradeTiming(limits, timing);

  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].passed());
  EXPECT_DOUBLE_EQ(results[0].value(), 0.0061);
  EXPECT_EQ(results[0].note(), "stream vio");
}

TEST(TimingChecksTest, DutLatencyIsNotEvaluatedWhenTheDutMeasuresNone) {
  TimingLimits limits;
  limits.dut_latency_p99_max_s = 0.005;

  const auto results = GradeTiming(limits, RealtimeFigures());

  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].evaluated());
  EXPECT_TRUE(results[0].passed());
  EXPECT_THAT(results[0].note(), HasSubstr("measures no latency"));
}

TEST(TimingChecksTest, LockstepRunsAreNotEvaluatedAndPass) {
  TimingLimits limits;
  limits.loop_period_p99_max_s = 0.001;
  limits.late_tick_fraction_max = 0;
  proto::Timing timing;
  timing.set_mode("lockstep");
  timing.set_ticks(1000);

  const auto results = GradeTiming(limits, timing);

  ASSERT_EQ(results.size(), 2u);
  for (const auto& result : results) {
    EXPECT_FALSE(result.evaluated());
    EXPECT_TRUE(result.passed());
    EXPECT_EQ(result.note(), "not evaluated (lockstep)");
  }
}

TEST(TimingChecksTest, ARealtimeRunWithoutTicksFailsItsChecks) {
  TimingLimits limits;
  limits.loop_period_p99_max_s = 0.002;
  limits.late_tick_fraction_max = 0.05;
  proto::Timing timing;
  timing.set_mode("realtime");

  const auto results = GradeTiming(limits, timing);

  ASSERT_EQ(results.size(), 2u);
  for (const auto& result : results) {
    EXPECT_TRUE(result.evaluated());
    EXPECT_FALSE(result.passed()) << result.name();
    EXPECT_DOUBLE_EQ(result.value(), 0.0);
  }
}

}  // namespace
}  // namespace hilrig::host
