// A run's DUT traffic logged as the runner exchanges it and replayed on a DUT: the same firmware
// gives no difference at any tick, a different one parts at the first command, and the log's
// messages decode to what was exchanged (inputs, CAN frames with their tactile fields, steps and
// commands). Differences treat NaN as a value of its own.
#include "host/replay/replay.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/replay/dut_traffic_log.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_loader.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

ScenarioConfig ShortHover() {
  const auto spec = ParseScenario(R"(name: "air"
vehicle { initial_position_m { z: 1 } }
timeline { at_s: 0.1 setpoint { position_m { x: 0.2 z: 1 } } }
simulation { duration_s: 0.5 }
)",
                                  "test.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), 1);
}

// The run's log with its DUT's traffic, read back.
mcap::McapContents RecordedRun(const ScenarioConfig& config) {
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, {});
  EXPECT_TRUE(log.ok());
  proto::RunRecording recording;
  recording.mutable_spec()->set_name(config.name);
  auto traffic = DutTrafficLog::Open(*log.value(), recording);
  EXPECT_TRUE(traffic.ok());
  const rig::SimClock wall_clock;
  RunControl control;
  control.wall_clock = &wall_clock;
  control.dut_traffic = traffic.value().get();
  (void)RunScenario(config, {}, control);
  EXPECT_TRUE(log.value()->Close().ok());
  mcap::McapReadResult read = mcap::ReadMcap(out.str());
  EXPECT_TRUE(read.ok()) << read.error->detail;
  return std::move(read.contents);
}

ReplayOutcome ReplayOn(const mcap::McapContents& contents, const ScenarioConfig& dut_config) {
  auto traffic = RecordedTraffic::Of(contents);
  EXPECT_TRUE(traffic.ok()) << traffic.error().message;
  auto owned_bus = std::make_unique<ReplayCanBus>();
  ReplayCanBus& bus = *owned_bus;
  InProcessDut dut(FirmwareFor(dut_config), std::move(owned_bus), 0.001);
  auto outcome = ReplayTraffic(contents, traffic.value(), dut, bus, 1e-9, nullptr);
  EXPECT_TRUE(outcome.ok()) << outcome.error().message;
  return outcome.ok() ? outcome.value() : ReplayOutcome();
}

TEST(ReplayTest, TheSameFirmwareGivesNoDifferenceAtAnyTick) {
  const ScenarioConfig config = ShortHover();
  const ReplayOutcome outcome = ReplayOn(RecordedRun(config), config);
  EXPECT_EQ(outcome.steps, 500u);
  EXPECT_EQ(outcome.commands_compared, 500u);
  EXPECT_EQ(outcome.commands_unmatched, 0u);
  EXPECT_GT(outcome.inputs, 1000u);  // IMU and setpoint every tick, VIO
  EXPECT_FALSE(outcome.differs());
  for (const OutputComparison& output : outcome.outputs) {
    EXPECT_EQ(output.largest, 0.0) << DutOutputName(output.output);
  }
}

TEST(ReplayTest, AFirmwareForAnotherMassPartsAtTheRotorsOnTheFirstTick) {
  const ScenarioConfig config = ShortHover();
  ScenarioConfig heavier = config;
  heavier.vehicle.body.mass_kg *= 1.01;
  const ReplayOutcome outcome = ReplayOn(RecordedRun(config), heavier);
  ASSERT_TRUE(outcome.differs());
  const OutputComparison* first = outcome.FirstParted();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->output, DutOutput::kRotorThrust);
  EXPECT_EQ(first->first_past_tick, 0u);
  EXPECT_GT(first->largest, 0.01);
}

TEST(ReplayTest, TheLogsMessagesDecodeToWhatWasExchanged) {
  const mcap::McapContents contents = RecordedRun(ShortHover());
  auto traffic = RecordedTraffic::Of(contents);
  ASSERT_TRUE(traffic.ok()) << traffic.error().message;
  EXPECT_EQ(traffic.value().recording().spec().name(), "air");
  int imu = 0, setpoints = 0, steps = 0, commands = 0;
  double last_setpoint_x_m = 0;
  for (const mcap::McapMessage& message : contents.messages) {
    auto event = traffic.value().Decode(message);
    ASSERT_TRUE(event.ok()) << event.error().message;
    if (!event.value()) continue;
    if (const auto* input = std::get_if<DutInput>(&*event.value())) {
      imu += std::holds_alternative<ImuMessage>(*input);
      if (const auto* setpoint = std::get_if<SetpointMessage>(input)) {
        ++setpoints;
        if (setpoint->stamp.time_ns < 100'000'000) {
          EXPECT_EQ(setpoint->position_m.x(), 0.0);
        }
        last_setpoint_x_m = setpoint->position_m.x();
      }
    }
    steps += std::holds_alternative<RecordedStep>(*event.value());
    if (const auto* command = std::get_if<RecordedCommand>(&*event.value())) {
      EXPECT_EQ(command->tick, static_cast<std::uint64_t>(commands));
      EXPECT_EQ(command->time_ns, commands * 1'000'000LL);
      ++commands;
    }
  }
  EXPECT_EQ(imu, 500);
  EXPECT_EQ(setpoints, 500);
  EXPECT_GT(last_setpoint_x_m, 0.0);
  EXPECT_EQ(steps, 500);
  EXPECT_EQ(commands, 500);
}

TEST(ReplayTest, ACanFrameIsLoggedAndDecodesBackAtItsTime) {
  const rig::CanFrame frame = rig::EncodeTactileSample({.node_id = 3, .code = {100, 200, 65000}});

  // Through a log and back: the same frame at the same time.
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, {});
  ASSERT_TRUE(log.ok());
  auto traffic_log = DutTrafficLog::Open(*log.value(), {});
  ASSERT_TRUE(traffic_log.ok());
  traffic_log.value()->Received({frame, 1'234'000});
  ASSERT_TRUE(log.value()->Close().ok());
  const mcap::McapReadResult read = mcap::ReadMcap(out.str());
  ASSERT_TRUE(read.ok());
  auto traffic = RecordedTraffic::Of(read.contents);
  ASSERT_TRUE(traffic.ok());
  auto event = traffic.value().Decode(read.contents.messages.back());
  ASSERT_TRUE(event.ok() && event.value());
  const auto& timed = std::get<rig::TimedCanFrame>(*event.value());
  EXPECT_EQ(timed.time_ns, 1'234'000);
  EXPECT_EQ(timed.frame, frame);
}

TEST(ReplayTest, ALogWithoutItsRecordingOrWithAnAlienChannelIsRefused) {
  std::ostringstream out;
  auto log = RunLogWriter::Open(out, {});
  ASSERT_TRUE(log.ok());
  ASSERT_TRUE(log.value()->Close().ok());
  mcap::McapReadResult read = mcap::ReadMcap(out.str());
  auto traffic = RecordedTraffic::Of(read.contents);
  ASSERT_FALSE(traffic.ok());
  EXPECT_NE(traffic.error().message.find("/run/recording"), std::string::npos);

  std::ostringstream alien;
  auto other = RunLogWriter::Open(alien, {});
  ASSERT_TRUE(other.ok());
  ASSERT_TRUE(DutTrafficLog::Open(*other.value(), {}).ok());
  ASSERT_TRUE(other.value()->AddChannel(*proto::TimelineMark::descriptor(), kDutStepTopic).ok());
  ASSERT_TRUE(other.value()->Close().ok());
  read = mcap::ReadMcap(alien.str());
  traffic = RecordedTraffic::Of(read.contents);
  ASSERT_FALSE(traffic.ok());
  EXPECT_NE(traffic.error().message.find("hilrig.proto.TimelineMark"), std::string::npos);
}

// A DUT that answers the first ticks and then fails (a link that broke).
class FailingDut final : public DutPort {
 public:
  explicit FailingDut(std::uint64_t failing_tick) : failing_tick_(failing_tick) {}
  void Send(const DutInput&) override {}
  rig::Result<ActuatorMessage> Step(std::uint64_t tick, std::int64_t) override {
    if (tick >= failing_tick_) return rig::MakeError("the link broke");
    return ActuatorMessage();
  }
  DutCounters counters() const override { return {}; }
  std::string description() const override { return "failing"; }

 private:
  std::uint64_t failing_tick_;
};

TEST(ReplayTest, ADutThatFailsAStepEndsTheReplayThere) {
  const mcap::McapContents contents = RecordedRun(ShortHover());
  auto traffic = RecordedTraffic::Of(contents);
  ASSERT_TRUE(traffic.ok());
  ReplayCanBus bus;
  FailingDut dut(3);
  auto outcome = ReplayTraffic(contents, traffic.value(), dut, bus, 1e-9, nullptr);
  ASSERT_TRUE(outcome.ok());
  EXPECT_TRUE(outcome.value().differs());
  ASSERT_TRUE(outcome.value().dut_failure.has_value());
  EXPECT_EQ(outcome.value().dut_failure->message, "the link broke");
  EXPECT_EQ(outcome.value().dut_failure_tick, 3u);
  EXPECT_EQ(outcome.value().steps, 4u);
  EXPECT_EQ(outcome.value().commands_compared, 3u);
}

TEST(ReplayTest, ADifferenceTakesNanAsAValueOfItsOwn) {
  ActuatorMessage a, b;
  EXPECT_EQ(OutputDifference(DutOutput::kServoAngle, a, b), 0.0);
  a.servo_angle_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isinf(OutputDifference(DutOutput::kServoAngle, a, b)));
  b.servo_angle_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(OutputDifference(DutOutput::kServoAngle, a, b), 0.0);
  a.tactile_force_sensor_n[4] = Eigen::Vector3d(0, 0.5, 0);
  EXPECT_EQ(OutputDifference(DutOutput::kTactileForce, a, b), 0.5);
  a.armed = true;
  EXPECT_EQ(OutputDifference(DutOutput::kArmed, a, b), 1.0);
}

}  // namespace
}  // namespace hilrig::host
