// The report's target section and the spec's target envelopes: a DUT on a target of its own puts
// its board, memory and work per control step into the report (as cycles and as fractions of the
// control period at its core clock), and a limit on that work counts in the verdict; a DUT on the
// host leaves the section out and the limits not evaluated. The spec's target envelopes are
// checked before a run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "host/runner/runner.h"
#include "host/runner/timing_checks.h"
#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// Answers every step with an idle command and reports `target`.
class TargetDut final : public DutPort {
 public:
  explicit TargetDut(std::optional<TargetSummary> target) : target_(std::move(target)) {}
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t) override {
    ActuatorMessage command;
    command.answers_sequence = tick;
    return command;
  }
  DutCounters counters() const override { return counters_; }
  std::string description() const override { return "target dut"; }
  std::optional<TargetSummary> target() const override { return target_; }

  DutCounters counters_;

 private:
  std::optional<TargetSummary> target_;
};

TargetSummary Stm32(std::uint32_t p99_cycles) {
  TargetSummary target;
  target.board = "stm32f405";
  target.core_clock_hz = 168'000'000;
  target.flash_used_bytes = 41'000;
  target.ram_used_bytes = 6'000;
  target.steps_measured = 10;
  target.work_p50_cycles = 16'800;
  target.work_p99_cycles = p99_cycles;
  target.work_max_cycles = p99_cycles;
  return target;
}

proto::Report RunWith(std::optional<TargetSummary> target, const std::string& envelopes,
                      std::uint64_t sensor_bytes_missing = 0, std::ostream* notes = nullptr) {
  const auto spec = ParseScenario(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 0.01 control_rate_hz: 500 }
)" + envelopes,
                                  "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  const ScenarioConfig config = ResolveScenario(spec.value(), 1);
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.dut_factory = [target, sensor_bytes_missing](
                            const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                            double) -> rig::Result<std::unique_ptr<DutPort>> {
    auto dut = std::make_unique<TargetDut>(target);
    dut->counters_.sensor_bytes_missing = sensor_bytes_missing;
    return std::unique_ptr<DutPort>(std::move(dut));
  };
  RunSinks sinks;
  sinks.progress = notes;
  return RunScenario(config, sinks, control);
}

TEST(TargetReportTest, ATargetDutsWorkIsReportedAgainstTheControlPeriod) {
  const proto::Report report = RunWith(Stm32(33'600), "");
  ASSERT_TRUE(report.has_target());
  const proto::Target& target = report.target();
  EXPECT_EQ(target.board(), "stm32f405");
  EXPECT_EQ(target.flash_used_bytes(), 41'000u);
  EXPECT_EQ(target.control_period_s(), 0.002);  // 500 Hz control
  EXPECT_EQ(target.work_p99_cycles(), 33'600u);
  // 336 000 cycles in a 2 ms period at 168 MHz.
  EXPECT_DOUBLE_EQ(target.work_p50_fraction(), 0.05);
  EXPECT_DOUBLE_EQ(target.work_p99_fraction(), 0.1);
  EXPECT_TRUE(report.passed());
  EXPECT_EQ(report.target_checks_size(), 0);
}

TEST(TargetReportTest, WorkOverTheScenesEnvelopeFailsTheRun) {
  const std::string envelopes = "target { work_p99_fraction_max: 0.5 work_max_fraction_max: 0.9 }";
  const proto::Report within = RunWith(Stm32(33'600), envelopes);
  ASSERT_EQ(within.target_checks_size(), 2);
  EXPECT_TRUE(within.target_checks(0).evaluated());
  EXPECT_TRUE(within.target_checks(0).passed());
  EXPECT_EQ(within.target_checks(0).name(), "work_p99_fraction_max");
  EXPECT_TRUE(within.passed());

  const proto::Report over = RunWith(Stm32(200'000), envelopes);  // 0.6 of the period
  ASSERT_EQ(over.target_checks_size(), 2);
  EXPECT_FALSE(over.target_checks(0).passed());
  EXPECT_DOUBLE_EQ(over.target_checks(0).value(), 200'000 / 336'000.0);
  EXPECT_TRUE(over.target_checks(1).passed());
  EXPECT_FALSE(over.passed());
}

TEST(TargetReportTest, AHostDutHasNoTargetAndItsLimitsAreNotEvaluated) {
  const proto::Report report = RunWith(std::nullopt, "target { work_p99_fraction_max: 0.5 }");
  EXPECT_FALSE(report.has_target());
  ASSERT_EQ(report.target_checks_size(), 1);
  EXPECT_FALSE(report.target_checks(0).evaluated());
  EXPECT_THAT(report.target_checks(0).note(), HasSubstr("the DUT runs on the host"));
  EXPECT_TRUE(report.passed());
}

TEST(TargetReportTest, ATargetThatMeasuredNothingFailsItsLimits) {
  TargetSummary silent = Stm32(0);
  silent.steps_measured = 0;
  const proto::Report report = RunWith(silent, "target { work_max_fraction_max: 0.5 }");
  ASSERT_EQ(report.target_checks_size(), 1);
  EXPECT_TRUE(report.target_checks(0).evaluated());
  EXPECT_FALSE(report.target_checks(0).passed());
  EXPECT_FALSE(report.passed());
}

TEST(TargetReportTest, ADutWithoutACoreClockMeasuresNothingAndIsNotEvaluated) {
  TargetSummary host_float = Stm32(0);
  host_float.board = "dut_emu 42";
  host_float.core_clock_hz = 0;
  host_float.steps_measured = 0;
  const proto::Report report = RunWith(host_float, "target { work_p99_fraction_max: 0.5 }");
  ASSERT_TRUE(report.has_target());
  ASSERT_EQ(report.target_checks_size(), 1);
  EXPECT_FALSE(report.target_checks(0).evaluated());
  EXPECT_THAT(report.target_checks(0).note(), HasSubstr("no core clock"));
  EXPECT_TRUE(report.passed());
}

TEST(TargetReportTest, TheSpecsTargetEnvelopesAreFractions) {
  const auto spec =
      ParseScenario("name: \"t\"\ntarget { work_p99_fraction_max: 1.5 }\n", "spec.textproto");
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(spec.error().message,
              HasSubstr("spec.textproto:2:10: target.work_p99_fraction_max: must be a fraction"));
}

TEST(TargetReportTest, ABoardThatSteppedWithoutItsSensorBytesIsWarnedOf) {
  std::ostringstream notes;
  const proto::Report report = RunWith(Stm32(33'600), "", 38, &notes);
  EXPECT_THAT(notes.str(), HasSubstr("air: warning: the dut stepped without 38 sensor bytes"));
  EXPECT_TRUE(report.passed());  // a real line may lose bytes: said, not failed

  std::ostringstream quiet;
  RunWith(Stm32(33'600), "", 0, &quiet);
  EXPECT_THAT(quiet.str(), Not(HasSubstr("warning")));
}

}  // namespace
}  // namespace hilrig::host
