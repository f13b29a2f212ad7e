#include "host/runner/runner.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <sstream>
#include <vector>

#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

ScenarioConfig ConfigFrom(const std::string& text, std::uint64_t seed = 1) {
  const auto spec = ParseScenario(text, "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), seed);
}

struct RunOutput {
  proto::Report report;
  std::string trace;
  std::string can_log;
};

RunOutput RunToEnd(const ScenarioConfig& config) {
  std::ostringstream trace, can_log;
  const rig::SimClock wall_clock;  // a clock that never moves: these tests ignore timing
  RunOutput output;
  output.report =
      RunScenario(config, {.trace_csv = &trace, .can_log = &can_log}, {.wall_clock = &wall_clock});
  output.trace = trace.str();
  output.can_log = can_log.str();
  return output;
}

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return 0;
}

constexpr const char* kHoverInAir = R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 3 }
timeline { at_s: 0 setpoint { position_m { z: 1 } } }
envelopes { name: "alt" signal: ALTITUDE_ERROR_M upper: 0.05 }
)";

// A wall clock that moves 5 s each time it is read: every look the runner takes at it is a
// progress moment.
class FiveSecondsPerRead final : public rig::Clock {
 public:
  std::int64_t NowNs() const override { return now_ns_ += 5'000'000'000; }

 private:
  mutable std::int64_t now_ns_ = 0;
};

// Counts the flushes that reach it.
class SyncCountingBuffer final : public std::stringbuf {
 public:
  int syncs = 0;

 protected:
  int sync() override {
    ++syncs;
    return std::stringbuf::sync();
  }
};

// The trace and the CAN log reach their files every few wall seconds (not only when their
// buffers fill), so a process that is killed keeps all but its last seconds.
TEST(RunnerTest, TraceAndCanLogAreFlushedEveryFewWallSeconds) {
  ScenarioConfig config = ConfigFrom(kHoverInAir);
  config.duration_s = 40;  // about ten looks at the wall clock, one per 4096 ticks
  SyncCountingBuffer trace_buffer, can_buffer;
  std::ostream trace(&trace_buffer), can_log(&can_buffer);
  const FiveSecondsPerRead wall_clock;

  const proto::Report report =
      RunScenario(config, {.trace_csv = &trace, .can_log = &can_log}, {.wall_clock = &wall_clock});

  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_GE(trace_buffer.syncs, 5);
  EXPECT_GE(can_buffer.syncs, 5);
  EXPECT_FALSE(trace_buffer.str().empty());
}

// The run's folder says how far a run that never finishes got: after each flush the runner hands
// on the simulated time the flushed trace reaches.
TEST(RunnerTest, EachFlushReportsTheSimulatedTimeItReached) {
  ScenarioConfig config = ConfigFrom(kHoverInAir);
  config.duration_s = 40;
  SyncCountingBuffer trace_buffer;
  std::ostream trace(&trace_buffer);
  const FiveSecondsPerRead wall_clock;
  std::vector<double> reached_s;
  std::vector<int> syncs_before;
  const auto flushed = [&](double simulated_s) {
    reached_s.push_back(simulated_s);
    syncs_before.push_back(trace_buffer.syncs);
  };

  RunScenario(config, {.trace_csv = &trace, .flushed = flushed}, {.wall_clock = &wall_clock});

  ASSERT_GE(reached_s.size(), 5u);
  EXPECT_GT(reached_s.front(), 0.0);
  EXPECT_TRUE(std::is_sorted(reached_s.begin(), reached_s.end()));
  EXPECT_LE(reached_s.back(), 40.0);
  for (std::size_t i = 0; i < syncs_before.size(); ++i) {
    EXPECT_GT(syncs_before[i], i == 0 ? 0 : syncs_before[i - 1]) << "the trace is flushed first";
  }
}

// A tick of a DUT on QEMU takes milliseconds of wall time: a lockstep run looks at a stop request
// every tick, so Ctrl-C ends it at the next one whatever the DUT.
TEST(RunnerTest, AStopRequestEndsALockstepRunAtTheNextTick) {
  ScenarioConfig config = ConfigFrom(kHoverInAir);
  config.duration_s = 40;
  const rig::SimClock wall_clock;
  const std::atomic<bool> stop_requested{true};

  const proto::Report report =
      RunScenario(config, {}, {.wall_clock = &wall_clock, .stop_requested = &stop_requested});

  EXPECT_EQ(report.stop_reason(), "interrupted");
  EXPECT_EQ(report.stop_kind(), proto::STOP_INTERRUPTED);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.ticks(), 1u);
}

TEST(RunnerTest, RunsForItsDurationAndCompletes) {
  const RunOutput output = RunToEnd(ConfigFrom(kHoverInAir));
  EXPECT_EQ(output.report.stop_reason(), "completed");
  EXPECT_EQ(output.report.stop_kind(), proto::STOP_COMPLETED);
  EXPECT_EQ(output.report.ticks(), 3000u);
  EXPECT_DOUBLE_EQ(output.report.simulated_s(), 3.0);
  EXPECT_TRUE(output.report.passed());
}

proto::Report RunWithDutThatFailsToStart(const rig::Error& error) {
  const rig::SimClock wall_clock;
  RunControl control{.wall_clock = &wall_clock};
  control.dut_factory = [&error](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                                 double) -> rig::Result<std::unique_ptr<DutPort>> { return error; };
  return RunScenario(ConfigFrom(kHoverInAir), {}, control);
}

TEST(RunnerTest, ADutThatFailsToStartEndsTheRunBeforeItsFirstTick) {
  const proto::Report report =
      RunWithDutThatFailsToStart(rig::MakeError("no dut_emu executable at /nowhere"));
  EXPECT_EQ(report.stop_kind(), proto::STOP_DUT_FAILED_TO_START);
  EXPECT_EQ(report.stop_detail(), "no dut_emu executable at /nowhere");
  EXPECT_EQ(report.stop_reason(), "dut failed to start: no dut_emu executable at /nowhere");
  EXPECT_EQ(report.ticks(), 0u);
  EXPECT_FALSE(report.passed());
}

// A DUT start that a stop request cut short is the user's doing, not the DUT's failure.
TEST(RunnerTest, ADutStartAStopRequestEndedIsAnInterruptedRun) {
  const proto::Report report = RunWithDutThatFailsToStart(
      rig::MakeError(rig::ErrorCode::kInterrupted, "stopped while waiting for the dut"));
  EXPECT_EQ(report.stop_kind(), proto::STOP_INTERRUPTED);
  EXPECT_EQ(report.stop_reason(), "interrupted");
  EXPECT_FALSE(report.passed());
}

TEST(RunnerTest, TraceHasOneRowPerTraceTick) {
  const RunOutput output = RunToEnd(ConfigFrom(kHoverInAir));
  const auto rows = std::count(output.trace.begin(), output.trace.end(), '\n');
  EXPECT_EQ(rows, 1 + 300);  // header + 100 Hz for 3 s
}

// A row every trace interval of ticks (1 kHz / 125 Hz: every 8), counted from the start.
TEST(RunnerTest, TraceRowsFallEveryTraceIntervalOfTicks) {
  const RunOutput output = RunToEnd(ConfigFrom(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 0.1 trace_rate_hz: 125 }
)"));
  const auto rows = std::count(output.trace.begin(), output.trace.end(), '\n');
  EXPECT_EQ(rows, 1 + 12);  // header + ticks 8, 16, ..., 96
  EXPECT_THAT(output.trace, HasSubstr("\n0.008,"));
  EXPECT_THAT(output.trace, HasSubstr("\n0.096,"));
}

// Records the control ticks the runner steps the DUT at, answering each with an idle command.
class StepRecordingDut final : public DutPort {
 public:
  explicit StepRecordingDut(std::vector<std::pair<std::uint64_t, std::int64_t>>& steps)
      : steps_(steps) {}
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t now_ns) override {
    steps_.emplace_back(tick, now_ns);
    return ActuatorMessage{};
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "step recorder"; }

 private:
  std::vector<std::pair<std::uint64_t, std::int64_t>>& steps_;
};

TEST(RunnerTest, ControlTicksComeEveryControlPeriodNumberedFromZero) {
  const ScenarioConfig config = ConfigFrom(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 0.01 control_rate_hz: 250 }
)");
  std::vector<std::pair<std::uint64_t, std::int64_t>> steps;
  const rig::SimClock wall_clock;
  RunControl control{.wall_clock = &wall_clock};
  control.dut_factory = [&steps](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                                 double) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<StepRecordingDut>(steps));
  };
  EXPECT_EQ(RunScenario(config, {}, control).ticks(), 10u);
  const std::vector<std::pair<std::uint64_t, std::int64_t>> expected = {
      {0, 0}, {1, 4'000'000}, {2, 8'000'000}};
  EXPECT_EQ(steps, expected);
}

TEST(RunnerTest, ReferenceMagnetometerFramesReachTheDutOverCan) {
  const RunOutput output = RunToEnd(ConfigFrom(kHoverInAir));
  // Node 7 for 3 s: samples at 50 Hz plus its status frame at 1 Hz.
  EXPECT_EQ(Metric(output.report, "dut_sensor_samples"), 150);
  EXPECT_EQ(Metric(output.report, "dut_can_frames_received"), 153);
  EXPECT_EQ(Metric(output.report, "dut_can_frames_rejected"), 0);
  EXPECT_EQ(Metric(output.report, "dut_sensor_samples_lost"), 0);
  EXPECT_EQ(output.report.can_frames_logged(), 153u);
}

TEST(RunnerTest, AbortingEnvelopeStopsTheRunAtItsFirstViolation) {
  const RunOutput output = RunToEnd(ConfigFrom(R"(name: "abort"
simulation { duration_s: 10 }
timeline { at_s: 0 setpoint { position_m { z: 1 } transition_s: 2 } }
envelopes { name: "low" signal: ALTITUDE_M upper: 0.2 abort_on_violation: true }
)"));
  EXPECT_THAT(output.report.stop_reason(), HasSubstr("aborted by envelope low"));
  EXPECT_EQ(output.report.stop_kind(), proto::STOP_ABORTED);
  EXPECT_EQ(output.report.stop_detail(), "low");
  EXPECT_LT(output.report.simulated_s(), 3.0);
  EXPECT_FALSE(output.report.passed());
}

TEST(RunnerTest, DisturbancePushesTheVehicleAndItRecovers) {
  const std::string spec = std::string(kHoverInAir) +
                           "timeline { at_s: 1 disturbance { force_world_n { x: 2 } duration_s: "
                           "0.5 } }\n";
  const RunOutput calm = RunToEnd(ConfigFrom(kHoverInAir));
  const RunOutput pushed = RunToEnd(ConfigFrom(spec));
  EXPECT_GT(Metric(pushed.report, "horizontal_error_max"),
            5 * Metric(calm.report, "horizontal_error_max"));
  EXPECT_LT(Metric(pushed.report, "horizontal_error_max"), 0.5);
}

TEST(RunnerTest, NoiseOffMakesTheSeedIrrelevant) {
  const std::string spec = std::string(kHoverInAir) + "models { noise: NOISE_OFF }\n";
  EXPECT_EQ(RunToEnd(ConfigFrom(spec, 1)).trace, RunToEnd(ConfigFrom(spec, 2)).trace);
}

TEST(RunnerTest, NoiseOnMakesTheSeedMatter) {
  EXPECT_NE(RunToEnd(ConfigFrom(kHoverInAir, 1)).trace, RunToEnd(ConfigFrom(kHoverInAir, 2)).trace);
}

TEST(RunnerTest, ReportListsEveryModelBuilt) {
  const RunOutput output = RunToEnd(ConfigFrom(kHoverInAir));
  std::vector<std::string> names;
  for (const auto& model : output.report.models()) names.push_back(model.name());
  EXPECT_THAT(names, ::testing::UnorderedElementsAre("vehicle", "rotors", "imu", "vio",
                                                     "reference_magnetometer", "can_bus", "dut"));
}

TEST(RunnerTest, TactileSceneCarriesSevenNodesOverCanAndPadsReadZeroForce) {
  ScenarioConfig config = ConfigFrom(std::string(kHoverInAir) + R"(
models { tactile { enabled: true field_fidelity: "map:8" } }
envelopes { name: "pads" signal: TACTILE_FORCE_N upper: 0.05 from_s: 1.2 }
)");
  ASSERT_TRUE(LoadTactileCalibration(config).ok());
  const RunOutput output = RunToEnd(config);
  EXPECT_EQ(Metric(output.report, "dut_sensor_samples"), 7 * 150);
  EXPECT_EQ(Metric(output.report, "dut_can_frames_received"), 7 * 153);
  EXPECT_EQ(Metric(output.report, "dut_can_frames_rejected"), 0);
  EXPECT_EQ(output.report.envelopes(1).verdict(), proto::PASS);
  EXPECT_GT(output.report.envelopes(1).samples_checked(), 100u);
  std::vector<std::string> names;
  for (const auto& model : output.report.models()) names.push_back(model.name());
  EXPECT_THAT(names, ::testing::Contains("tactile_pads"));
}

TEST(RunnerTest, SevenNodesAt50HzLoadTheBusUnderFivePercent) {
  ScenarioConfig config = ConfigFrom(
      std::string(kHoverInAir) + R"(models { tactile { enabled: true field_fidelity: "map:8" } })");
  ASSERT_TRUE(LoadTactileCalibration(config).ok());
  const double load = Metric(RunToEnd(config).report, "can_bus_load");
  EXPECT_GT(load, 0.03);
  EXPECT_LT(load, 0.05);
}

TEST(RunnerTest, ReportShowsTheLowestPriorityNodesArbitrationLatencyAt1kHz) {
  ScenarioConfig config = ConfigFrom(std::string(kHoverInAir) + R"(
models { tactile { enabled: true field_fidelity: "map:8" node_rate_hz: 1000 } })");
  ASSERT_TRUE(LoadTactileCalibration(config).ok());
  const proto::Report report = RunToEnd(config).report;
  EXPECT_GT(Metric(report, "can_bus_load"), 0.9);
  // Node 7's sample (0x107) loses arbitration to the six others' samples.
  EXPECT_GT(Metric(report, "can_queueing_max_s_0x107"), 6 * 100e-6);
  EXPECT_GT(Metric(report, "can_queueing_mean_s_0x107"),
            Metric(report, "can_queueing_mean_s_0x101"));
}

TEST(RunnerTest, PadForceIsZeroWhileTheDutIsStillZeroing) {
  ScenarioConfig config = ConfigFrom(std::string(kHoverInAir) + R"(
models { tactile { enabled: true field_fidelity: "map:8" zeroing_s: 10 } }
envelopes { name: "pads" signal: TACTILE_FORCE_N upper: 0 }
)");
  ASSERT_TRUE(LoadTactileCalibration(config).ok());
  EXPECT_EQ(RunToEnd(config).report.envelopes(1).verdict(), proto::PASS);
}

TEST(RunnerTest, TickAfterTheEndDoesNothing) {
  const ScenarioConfig config = ConfigFrom(kHoverInAir);
  std::ostringstream trace;
  const rig::SimClock wall_clock;
  ScenarioRunner runner(config, {.trace_csv = &trace}, {.wall_clock = &wall_clock});
  int ticks = 0;
  while (runner.Tick()) ++ticks;
  EXPECT_EQ(ticks + 1, 3000);
  EXPECT_FALSE(runner.Tick());
  EXPECT_EQ(runner.Finish().ticks(), 3000u);
}

TEST(RunnerTest, FallingVehicleFailsAltitudeEnvelopeWithoutCrashing) {
  // Starting in the air with no setpoint the DUT holds its start; a vehicle too heavy to hold
  // itself with weak rotors comes down, and the envelope says so.
  const RunOutput output = RunToEnd(ConfigFrom(R"(name: "heavy"
vehicle { initial_position_m { z: 1 } mass_kg: 1.5 max_thrust_per_rotor_n: 3.8 }
simulation { duration_s: 8 }
envelopes { name: "alt" signal: ALTITUDE_M lower: 0.9 }
)"));
  EXPECT_EQ(output.report.envelopes(0).verdict(), proto::FAIL);
  EXPECT_GT(Metric(output.report, "ground_impacts"), 0);
}

}  // namespace
}  // namespace hilrig::host
