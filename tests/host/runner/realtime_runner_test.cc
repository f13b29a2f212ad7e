// The runner in real time, paced by FakePacingClock so that no wall time passes and every figure is
// an exact number: tick k waits until start + k * period, never sleeps when late, keeps its
// schedule after a stall, holds the last command while the DUT has not answered and counts the
// control ticks it missed; the DUT failing or Ctrl-C ends the run with a complete report.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <deque>
#include <memory>
#include <sstream>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

constexpr std::int64_t kMs = 1'000'000;
// The runner polls the DUT once at each control tick and once every 100 µs wait slice between
// ticks: 11 polls per 1 ms tick when nothing is late.
constexpr int kPollsPerTick = 11;

ScenarioConfig ConfigFrom(const std::string& text) {
  const auto spec = ParseScenario(text, "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), 1);
}

// One second at 1 kHz, the vehicle resting on the ground: nothing in the plant needs the DUT.
constexpr const char* kOnTheGround = R"(name: "ground"
models { rotors: ROTORS_INSTANTANEOUS }
simulation { duration_s: 1 }
)";

// A DUT under test control: it answers request k (when k % answer_every == 0, and only the first
// `max_answers`) `delay_polls` polls after it was made, with a fixed command; `fail_at_poll`
// makes that poll report a broken link.
struct ScriptedDutScript {
  int delay_polls = 1;
  int answer_every = 1;
  int max_answers = 1 << 30;
  int fail_at_poll = -1;
  ActuatorMessage command;
};

class ScriptedDut final : public DutPort {
 public:
  explicit ScriptedDut(ScriptedDutScript script) : script_(std::move(script)) {}

  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t, std::int64_t) override {
    return rig::MakeError("a real-time run must not call Step");
  }
  void RequestStep(std::uint64_t tick, std::int64_t) override {
    if (static_cast<int>(tick) % script_.answer_every != 0 || answers_ >= script_.max_answers) {
      return;
    }
    ++answers_;
    pending_.push_back({script_.delay_polls, tick});
  }
  rig::Result<std::optional<ActuatorMessage>> PollCommand() override {
    if (polls_++ == script_.fail_at_poll) return rig::MakeError("link closed by the DUT");
    std::optional<ActuatorMessage> newest;
    for (Pending& pending : pending_) --pending.polls_left;
    while (!pending_.empty() && pending_.front().polls_left <= 0) {
      newest = script_.command;
      newest->answers_sequence = pending_.front().tick;
      pending_.pop_front();
    }
    return newest;
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "scripted"; }

 private:
  struct Pending {
    int polls_left;
    std::uint64_t tick;
  };
  ScriptedDutScript script_;
  std::deque<Pending> pending_;
  int answers_ = 0;
  int polls_ = 0;
};

DutFactory Scripted(const ScriptedDutScript& script) {
  return [script](const ScenarioConfig&, std::unique_ptr<rig::CanBus>,
                  double) -> rig::Result<std::unique_ptr<DutPort>> {
    return std::unique_ptr<DutPort>(std::make_unique<ScriptedDut>(script));
  };
}

struct RealtimeRun {
  proto::Report report;
  TraceSample last_sample;
};

// Runs to the end; `work_ns` of wall time pass after each tick (before the next one is due).
RealtimeRun RunRealtime(const ScenarioConfig& config, const rig::FakePacingClock& clock,
                        const DutFactory& dut, std::int64_t work_ns = 0,
                        const std::atomic<bool>* stop = nullptr) {
  RealtimeRun run;
  RunSinks sinks;
  sinks.trace_sample = [&run](const TraceSample& sample) { run.last_sample = sample; };
  ScenarioRunner runner(config, sinks, {&clock, stop, dut, &clock});
  while (runner.Tick()) clock.AdvanceNs(work_ns);
  run.report = runner.Finish();
  return run;
}

ScriptedDutScript Silent() {
  ScriptedDutScript script;
  script.max_answers = 0;
  return script;
}

TEST(RealtimeRunnerTest, OnTimeTicksSleepUntilDueAndThePeriodIsExact) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;

  const proto::Timing timing = RunRealtime(config, clock, Scripted({})).report.timing();

  EXPECT_EQ(timing.mode(), "realtime");
  EXPECT_EQ(timing.ticks(), 1000u);
  // Every tick but the first (which sets the schedule) waits its 1 ms in ten 100 µs slices.
  EXPECT_EQ(clock.sleeps(), 999u * 10u);
  EXPECT_EQ(clock.NowNs(), 999 * kMs);
  EXPECT_DOUBLE_EQ(timing.loop_period_p50_s(), 0.001);
  EXPECT_DOUBLE_EQ(timing.loop_period_p99_s(), 0.001);
  EXPECT_DOUBLE_EQ(timing.loop_period_max_s(), 0.001);
  EXPECT_DOUBLE_EQ(timing.lateness_max_s(), 0.0);
  EXPECT_EQ(timing.late_ticks(), 0u);
  EXPECT_EQ(timing.stalls(), 0u);
}

// 1.5 ms of work per 1 ms tick: tick k starts k * 0.5 ms late, so ticks 3.. are over the 1 ms
// threshold, and the loop never sleeps.
TEST(RealtimeRunnerTest, WorkLongerThanThePeriodMakesTicksLateWithoutSleeping) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;

  const proto::Timing timing = RunRealtime(config, clock, Scripted({}), 1'500'000).report.timing();

  EXPECT_EQ(clock.sleeps(), 0u);
  EXPECT_EQ(timing.late_ticks(), 997u);
  EXPECT_DOUBLE_EQ(timing.loop_period_p50_s(), 0.0015);
  EXPECT_DOUBLE_EQ(timing.loop_period_max_s(), 0.0015);
  EXPECT_DOUBLE_EQ(timing.lateness_max_s(), 999 * 0.0005);
  EXPECT_EQ(timing.stalls(), 1u);  // it fell 100 ms behind at tick 201 and never caught up
}

// One 250 ms hang after tick 100: ticks 101..348 start late (by 249 ms down to 2 ms) as the loop
// catches up back to back, that is one stall, and the run still ends on its original schedule.
TEST(RealtimeRunnerTest, StallIsCountedOnceAndTheScheduleIsKept) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScenarioRunner runner(config, {}, {&clock, nullptr, Scripted({}), &clock});
  int ticks = 0;
  while (runner.Tick()) {
    if (++ticks == 101) clock.AdvanceNs(250 * kMs);
  }

  const proto::Timing timing = runner.Finish().timing();

  EXPECT_EQ(timing.late_ticks(), 248u);
  EXPECT_EQ(timing.stalls(), 1u);
  EXPECT_DOUBLE_EQ(timing.loop_period_max_s(), 0.25);
  EXPECT_DOUBLE_EQ(timing.lateness_max_s(), 0.249);
  EXPECT_EQ(clock.NowNs(), 999 * kMs);  // tick 999 at its due time: the epoch was not reset
}

// The trace sink runs inside the tick: 300 us there on every 10th tick is that tick's work.
TEST(RealtimeRunnerTest, WorkTimeIsMeasuredPerTick) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  RunSinks sinks;
  sinks.trace_sample = [&clock](const TraceSample&) { clock.AdvanceNs(300'000); };
  ScenarioRunner runner(config, sinks, {&clock, nullptr, Scripted({}), &clock});
  while (runner.Tick()) {
  }

  const proto::Timing timing = runner.Finish().timing();

  EXPECT_DOUBLE_EQ(timing.work_p50_s(), 1e-6);  // zero work reads as its 1 us bucket's upper edge
  EXPECT_DOUBLE_EQ(timing.work_p99_s(), 0.0003);
  EXPECT_DOUBLE_EQ(timing.work_max_s(), 0.0003);
  EXPECT_EQ(timing.late_ticks(), 0u);
}

// The DUT answers its first request only: that command (armed, 1 N per rotor) is held for the rest
// of the run, and every control tick after the one it arrived in is a miss.
TEST(RealtimeRunnerTest, TheLastCommandIsHeldWhileTheDutIsSilent) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScriptedDutScript script;
  script.max_answers = 1;
  script.command.armed = true;
  script.command.rotor_thrust_n = {1.0, 1.0, 1.0, 1.0};

  const RealtimeRun run = RunRealtime(config, clock, Scripted(script));

  for (double thrust_n : run.last_sample.rotor_thrust_n) EXPECT_DOUBLE_EQ(thrust_n, 1.0);
  EXPECT_EQ(run.report.timing().control_ticks(), 1000u);
  EXPECT_EQ(run.report.timing().dut_commands_missed(), 998u);  // all but ticks 0 and 1
}

TEST(RealtimeRunnerTest, NoCommandYetMeansRotorsOff) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;

  const RealtimeRun run = RunRealtime(config, clock, Scripted(Silent()));

  for (double thrust_n : run.last_sample.rotor_thrust_n) EXPECT_DOUBLE_EQ(thrust_n, 0.0);
  EXPECT_EQ(run.report.timing().dut_commands_missed(), 999u);
}

// Answers to even requests only, one poll later: a new command reaches the odd control ticks.
TEST(RealtimeRunnerTest, ADutAnsweringEveryOtherRequestMissesTheEvenTicks) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScriptedDutScript script;
  script.answer_every = 2;

  const proto::Timing timing = RunRealtime(config, clock, Scripted(script)).report.timing();

  EXPECT_EQ(timing.dut_commands_missed(), 499u);  // control ticks 2, 4, ..., 998
}

// The runner polls while it waits for the next tick: an answer half a period after the request
// is there for the next control tick.
TEST(RealtimeRunnerTest, AnAnswerArrivingWhileWaitingMakesTheNextControlTick) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScriptedDutScript script;
  script.delay_polls = kPollsPerTick / 2;

  const proto::Timing timing = RunRealtime(config, clock, Scripted(script)).report.timing();

  EXPECT_EQ(timing.dut_commands_missed(), 0u);
  EXPECT_EQ(timing.control_ticks(), 1000u);
}

TEST(RealtimeRunnerTest, ALateFirstAnswerMissesOnlyUntilItArrives) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScriptedDutScript script;
  script.delay_polls = 2 * kPollsPerTick + 3;  // a little over two periods

  const proto::Timing timing = RunRealtime(config, clock, Scripted(script)).report.timing();

  EXPECT_EQ(timing.dut_commands_missed(), 2u);  // control ticks 1 and 2
}

TEST(RealtimeRunnerTest, DutFailureEndsTheRunWithACompleteReport) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  ScriptedDutScript script;
  script.fail_at_poll = 40 * kPollsPerTick;  // the poll of control tick 40

  const proto::Report report = RunRealtime(config, clock, Scripted(script)).report;

  EXPECT_EQ(report.stop_reason(), "dut failed: link closed by the DUT");
  EXPECT_EQ(report.stop_kind(), proto::STOP_DUT_FAILED);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.ticks(), 40u);
  EXPECT_EQ(report.timing().ticks(), 41u);  // the tick that found the failure began
  EXPECT_EQ(report.timing().control_ticks(), 40u);
  EXPECT_THAT(report.models_size(), ::testing::Gt(0));
}

TEST(RealtimeRunnerTest, StopRequestEndsTheRunAfterOneTick) {
  const ScenarioConfig config = ConfigFrom(kOnTheGround);
  const rig::FakePacingClock clock;
  const std::atomic<bool> stop{true};

  const proto::Report report = RunRealtime(config, clock, Scripted({}), 0, &stop).report;

  EXPECT_EQ(report.stop_reason(), "interrupted");
  EXPECT_EQ(report.stop_kind(), proto::STOP_INTERRUPTED);
  EXPECT_EQ(report.ticks(), 1u);
}

// The in-process DUT answers at once (DutPort's default): each command reaches the plant one
// control tick later, none is missed, and the vehicle still hovers inside 5 cm.
TEST(RealtimeRunnerTest, InProcessDutMissesNothingAndHovers) {
  const ScenarioConfig config = ConfigFrom(R"(name: "hover"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 3 }
timeline { at_s: 0 setpoint { position_m { z: 1 } } }
envelopes { name: "alt" signal: ALTITUDE_ERROR_M upper: 0.05 }
)");
  const rig::FakePacingClock clock;

  const proto::Report report = RunRealtime(config, clock, DutFactory()).report;

  EXPECT_TRUE(report.passed()) << report.envelopes(0).worst_value();
  EXPECT_EQ(report.timing().dut_commands_missed(), 0u);
  EXPECT_EQ(report.timing().control_ticks(), 3000u);
}

constexpr const char* kTimedGround = R"(name: "ground"
simulation { duration_s: 1 }
timing { late_tick_fraction_max: 0.05 loop_period_p99_max_s: 0.002 }
)";

TEST(RealtimeRunnerTest, TimingEnvelopesFailARealtimeRunThatMissesThem) {
  const ScenarioConfig config = ConfigFrom(kTimedGround);
  const rig::FakePacingClock clock;

  const proto::Report report = RunRealtime(config, clock, Scripted({}), 1'500'000).report;

  EXPECT_EQ(report.stop_reason(), "completed");
  EXPECT_FALSE(report.passed());
  ASSERT_EQ(report.timing_checks_size(), 2);
  EXPECT_EQ(report.timing_checks(0).name(), "loop_period_p99_max_s");
  EXPECT_TRUE(report.timing_checks(0).passed());  // 1.5 ms <= 2 ms
  EXPECT_EQ(report.timing_checks(1).name(), "late_tick_fraction_max");
  EXPECT_FALSE(report.timing_checks(1).passed());
  EXPECT_DOUBLE_EQ(report.timing_checks(1).value(), 0.997);
}

TEST(RealtimeRunnerTest, TimingEnvelopesPassAnOnTimeRealtimeRun) {
  const ScenarioConfig config = ConfigFrom(kTimedGround);
  const rig::FakePacingClock clock;

  const proto::Report report = RunRealtime(config, clock, Scripted({})).report;

  EXPECT_TRUE(report.passed());
  for (const auto& check : report.timing_checks()) EXPECT_TRUE(check.evaluated()) << check.name();
}

TEST(RealtimeRunnerTest, LockstepListsTimingEnvelopesAsNotEvaluated) {
  const ScenarioConfig config = ConfigFrom(kTimedGround);
  const rig::SimClock wall_clock;

  const proto::Report report = RunScenario(config, {}, {&wall_clock, nullptr, {}, nullptr});

  EXPECT_TRUE(report.passed());
  EXPECT_EQ(report.timing().mode(), "lockstep");
  EXPECT_EQ(report.timing().ticks(), 1000u);
  ASSERT_EQ(report.timing_checks_size(), 2);
  for (const auto& check : report.timing_checks()) {
    EXPECT_FALSE(check.evaluated());
    EXPECT_THAT(check.note(), HasSubstr("lockstep"));
  }
}

}  // namespace
}  // namespace hilrig::host
