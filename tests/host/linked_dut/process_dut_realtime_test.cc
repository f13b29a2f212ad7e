// The DUT process in real time (RequestStep / PollCommand) with a real dut_emu on loopback. The
// wall clock the ProcessDut reads is a SimClock the test moves, so latencies and the watchdog are
// exact numbers; only the loops that wait for a reply to cross the socket are bounded by the
// steady clock (spinning polls, no sleeps).
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dut_emu/dut_emu_server.h"
#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/link/hil_link_codec.h"
#include "host/linked_dut/process_dut.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"
#include "tests/support/dut_inputs.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;
constexpr std::int64_t kTickNs = 1'000'000;
constexpr std::int64_t kReplyDeadlineNs = 5'000'000'000;  // a generous bound on a loopback reply

DutFirmware HoverFirmware() {
  return DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true};
}

ImuMessage ImuAt(std::uint64_t sequence, std::int64_t now_ns) {
  return {{sequence, now_ns},
          Eigen::Vector3d(0.01, -0.02, 0.003),
          Eigen::Vector3d(0.1, 0, QuadrotorParams{}.gravity_m_s2)};
}

void SendHoverReference(DutPort& dut) {
  dut.Send(VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
  dut.Send(SetpointMessage{
      {0, 0}, Eigen::Vector3d(0, 0, 1.2), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.3});
}

// Polls until a command or an error arrives, or the steady-clock deadline passes (then nullopt).
rig::Result<std::optional<ActuatorMessage>> PollUntilAnswer(ProcessDut& dut,
                                                            std::int64_t deadline_ns = 0) {
  const rig::SteadyClock steady;
  const std::int64_t give_up_ns =
      steady.NowNs() + (deadline_ns > 0 ? deadline_ns : kReplyDeadlineNs);
  while (steady.NowNs() < give_up_ns) {
    auto polled = dut.PollCommand();
    if (!polled || polled.value()) return polled;
  }
  return std::optional<ActuatorMessage>();
}

double Metric(const ProcessDut& dut, const std::string& name) {
  for (const auto& [metric, value, unit] : dut.link_metrics()) {
    if (metric == name) return value;
  }
  return -1;
}

rig::DurationSummary LatencyOf(const ProcessDut& dut, const std::string& stream) {
  for (const StreamLatency& latency : dut.response_latencies()) {
    if (latency.stream == stream) return latency.latency;
  }
  ADD_FAILURE() << "no latency for stream " << stream;
  return {};
}

class ProcessDutRealtimeTest : public ::testing::Test {
 protected:
  std::unique_ptr<ProcessDut> Start(std::vector<std::string> extra_args = {},
                                    double control_period_s = kControlPeriodS) {
    ProcessDutOptions options;
    options.dut_emu_path = ::hilrig::test_support::BinDir() + "/dut_emu";
    options.extra_args = std::move(extra_args);
    options.wall_clock = &wall_clock_;
    options.pacing = DutPacing::kRealtime;
    auto dut = ProcessDut::Launch(HoverFirmware(), bus_.Connect("dut"), control_period_s, options);
    EXPECT_TRUE(dut.ok()) << (dut.ok() ? "" : dut.error().message);
    return dut.ok() ? std::move(dut).value() : nullptr;
  }

  // One real-time tick that waits for its own answer: the IMU sample, the request, the answer.
  rig::Result<std::optional<ActuatorMessage>> Tick(ProcessDut& dut, std::uint64_t tick) {
    const std::int64_t now_ns = static_cast<std::int64_t>(tick) * kTickNs;
    dut.Send(ImuAt(tick - 1, now_ns));
    dut.RequestStep(tick, now_ns);
    return PollUntilAnswer(dut);
  }

  rig::SimClock wall_clock_;
  rig::EmulatedBus bus_;
};

TEST_F(ProcessDutRealtimeTest, AnswerEqualsTheLockstepAnswerForTheSameInputs) {
  rig::EmulatedBus reference_bus;
  InProcessDut reference(HoverFirmware(), reference_bus.Connect("dut"), kControlPeriodS);
  SendHoverReference(reference);
  ActuatorMessage expected;
  for (std::uint64_t tick = 1; tick <= 200; ++tick) {
    const std::int64_t now_ns = static_cast<std::int64_t>(tick) * kTickNs;
    reference.Send(ImuAt(tick - 1, now_ns));
    expected = reference.Step(tick, now_ns).value();
  }
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  std::optional<ActuatorMessage> actual;
  for (std::uint64_t tick = 1; tick <= 200; ++tick) {
    auto answer = Tick(*dut, tick);
    ASSERT_TRUE(answer.ok()) << answer.error().message;
    ASSERT_TRUE(answer.value().has_value()) << "no answer to tick " << tick;
    actual = answer.value();
  }
  ASSERT_TRUE(expected.armed);
  EXPECT_EQ(actual->answers_sequence, 200u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(actual->rotor_thrust_n[i], expected.rotor_thrust_n[i]);
  EXPECT_EQ(actual->estimated_position_m, expected.estimated_position_m);
  EXPECT_EQ(actual->servo_angle_rad, expected.servo_angle_rad);
}

// Every message is sent at a known fake wall time and every answer polled at another, so each
// stream's latency is a number the test knows: IMU sent at t, CAN frames and the request at
// t + 200 us, the answer polled at t + 500 us.
TEST_F(ProcessDutRealtimeTest, LatencyPerStreamFromTheSendTimesTheCommandCovers) {
  constexpr int kTicks = 20;
  // A 50 ms control period: dut_emu then waits up to 50 ms for each step's CAN frame, so no frame
  // slips to a later step on a loaded machine and every latency below is exact.
  auto dut = Start({}, 50e-3);
  ASSERT_NE(dut, nullptr);
  auto sensor_node = bus_.Connect("node");
  const std::array<std::uint8_t, 2> payload = {1, 2};
  SendHoverReference(*dut);  // VIO and setpoint at wall time 0
  for (std::uint64_t tick = 1; tick <= kTicks; ++tick) {
    const std::int64_t now_ns = static_cast<std::int64_t>(tick) * kTickNs;
    ASSERT_TRUE(sensor_node->Send(rig::CanFrame::Classic(0x42, payload), now_ns - 500'000).ok());
    wall_clock_.AdvanceNs(100'000);
    dut->Send(ImuAt(tick - 1, now_ns));
    wall_clock_.AdvanceNs(200'000);
    dut->RequestStep(tick, now_ns);
    wall_clock_.AdvanceNs(300'000);
    auto answer = PollUntilAnswer(*dut);
    ASSERT_TRUE(answer.ok()) << answer.error().message;
    ASSERT_TRUE(answer.value().has_value()) << "no answer to tick " << tick;
  }
  const rig::DurationSummary imu = LatencyOf(*dut, "imu");
  EXPECT_EQ(imu.count, static_cast<std::uint64_t>(kTicks));
  EXPECT_DOUBLE_EQ(imu.p50_s, 500e-6);
  EXPECT_DOUBLE_EQ(imu.max_s, 500e-6);
  const rig::DurationSummary can = LatencyOf(*dut, "can");
  EXPECT_EQ(can.count, static_cast<std::uint64_t>(kTicks));
  EXPECT_DOUBLE_EQ(can.max_s, 300e-6);
  const rig::DurationSummary command = LatencyOf(*dut, "command");
  EXPECT_EQ(command.count, static_cast<std::uint64_t>(kTicks));
  EXPECT_DOUBLE_EQ(command.p99_s, 300e-6);
  // The one VIO pose and setpoint, sent at 0, are covered by the first answer at 600 us.
  const rig::DurationSummary vio = LatencyOf(*dut, "vio");
  EXPECT_EQ(vio.count, 1u);
  EXPECT_DOUBLE_EQ(vio.max_s, 600e-6);
  EXPECT_EQ(LatencyOf(*dut, "setpoint").count, 1u);
  EXPECT_EQ(Metric(*dut, "dut_can_frame_waits_expired"), 0.0);
}

// Every stream the runner sends the DUT has its latency, named as the report names it, then the
// CAN frames and the command; each input stream is covered by the DUT's answer.
TEST_F(ProcessDutRealtimeTest, EveryDutInputStreamHasItsLatency) {
  auto dut = Start({}, 50e-3);
  ASSERT_NE(dut, nullptr);
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    dut->Send(test::DutInputAt(index));
  }
  wall_clock_.AdvanceNs(100'000);
  dut->RequestStep(1, kTickNs);
  wall_clock_.AdvanceNs(400'000);
  auto answer = PollUntilAnswer(*dut);
  ASSERT_TRUE(answer.ok()) << answer.error().message;
  ASSERT_TRUE(answer.value().has_value());
  const std::vector<StreamLatency> latencies = dut->response_latencies();
  ASSERT_EQ(latencies.size(), kDutInputStreams + 2);
  for (std::size_t index = 0; index < kDutInputStreams; ++index) {
    EXPECT_EQ(latencies[index].stream, DutInputStream(index));
    EXPECT_EQ(latencies[index].latency.count, 1u) << latencies[index].stream;
    EXPECT_DOUBLE_EQ(latencies[index].latency.max_s, 500e-6) << latencies[index].stream;
  }
  EXPECT_EQ(latencies[kDutInputStreams].stream, "can");
  EXPECT_EQ(latencies[kDutInputStreams + 1].stream, "command");
}

// The rig's own controller is never sent the navigation sensors: no latency line for them.
TEST_F(ProcessDutRealtimeTest, AStreamNeverSentHasNoLatency) {
  auto dut = Start({}, 50e-3);
  ASSERT_NE(dut, nullptr);
  dut->Send(ImuAt(0, kTickNs));
  dut->RequestStep(1, kTickNs);
  auto answer = PollUntilAnswer(*dut);
  ASSERT_TRUE(answer.ok()) << answer.error().message;
  std::vector<std::string> streams;
  for (const StreamLatency& latency : dut->response_latencies()) streams.push_back(latency.stream);
  EXPECT_EQ(streams, (std::vector<std::string>{"imu", "can", "command"}));
}

TEST_F(ProcessDutRealtimeTest, NewestCommandWinsAndTheOlderOnesAreCounted) {
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  for (std::uint64_t tick = 1; tick <= 3; ++tick) {
    dut->Send(ImuAt(tick - 1, static_cast<std::int64_t>(tick) * kTickNs));
    dut->RequestStep(tick, static_cast<std::int64_t>(tick) * kTickNs);
  }
  int polled_commands = 0;
  std::uint64_t newest = 0;
  while (newest < 3) {
    auto answer = PollUntilAnswer(*dut);
    ASSERT_TRUE(answer.ok()) << answer.error().message;
    ASSERT_TRUE(answer.value().has_value());
    ASSERT_GT(answer.value()->answers_sequence, newest);
    newest = answer.value()->answers_sequence;
    ++polled_commands;
  }
  EXPECT_EQ(Metric(*dut, "link_commands_received"), 3.0);
  EXPECT_EQ(Metric(*dut, "link_commands_superseded"), 3.0 - polled_commands);
  EXPECT_EQ(Metric(*dut, "link_requests_skipped"), 0.0);
}

TEST_F(ProcessDutRealtimeTest, KilledProcessIsNamedWithinASecond) {
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  for (std::uint64_t tick = 1; tick <= 5; ++tick) ASSERT_TRUE(Tick(*dut, tick).ok());
  ASSERT_EQ(::kill(dut->pid(), SIGKILL), 0);
  dut->Send(ImuAt(5, 6 * kTickNs));
  dut->RequestStep(6, 6 * kTickNs);
  // The fake wall clock stands still: the watchdog cannot fire, the death itself must be seen.
  const auto answer = PollUntilAnswer(*dut, 1'000'000'000);
  ASSERT_FALSE(answer.ok()) << "no error within 1 s of the kill";
  EXPECT_EQ(answer.error().message, "dut process killed by signal 9");
}

TEST_F(ProcessDutRealtimeTest, ProcessThatExitsIsNamedWithItsStatus) {
  auto dut = Start({"--test-exit-at-tick", "4"});
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  for (std::uint64_t tick = 1; tick <= 3; ++tick) ASSERT_TRUE(Tick(*dut, tick).ok());
  const auto answer = Tick(*dut, 4);
  ASSERT_FALSE(answer.ok());
  EXPECT_EQ(answer.error().message, "dut process exited with status 3");
}

TEST_F(ProcessDutRealtimeTest, WatchdogFiresOnTheWallClockAfterTheAnswerTimeout) {
  auto dut = Start({"--test-silent-at-tick", "3"});
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  for (std::uint64_t tick = 1; tick <= 2; ++tick) ASSERT_TRUE(Tick(*dut, tick).ok());
  dut->RequestStep(3, 3 * kTickNs);
  wall_clock_.AdvanceNs(1'000'000'000);  // exactly the 1 s timeout: not yet
  const auto at_timeout = dut->PollCommand();
  ASSERT_TRUE(at_timeout.ok()) << at_timeout.error().message;
  EXPECT_FALSE(at_timeout.value().has_value());
  wall_clock_.AdvanceNs(1'000);
  const auto past_timeout = dut->PollCommand();
  ASSERT_FALSE(past_timeout.ok());
  EXPECT_EQ(past_timeout.error().message, "the dut did not answer for 1 s (tick 3)");
  EXPECT_EQ(Metric(*dut, "link_watchdog_timeouts"), 1.0);
}

TEST_F(ProcessDutRealtimeTest, AnswerToATickNeverRequestedIsANamedCountedError) {
  auto dut = Start({"--test-wrong-tick-at-tick", "3"});
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  for (std::uint64_t tick = 1; tick <= 2; ++tick) ASSERT_TRUE(Tick(*dut, tick).ok());
  const auto answer = Tick(*dut, 3);
  ASSERT_FALSE(answer.ok());
  EXPECT_EQ(answer.error().message, "the dut answered tick " +
                                        std::to_string(3 + dut_emu::kWrongTickOffset) +
                                        ", which was never requested (last request: tick 3)");
  EXPECT_EQ(Metric(*dut, "link_unrequested_answers"), 1.0);
  const auto again = dut->PollCommand();  // the failure sticks
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, answer.error().message);
}

TEST_F(ProcessDutRealtimeTest, GarbageAnswerIsANamedCountedError) {
  auto dut = Start({"--test-garbage-at-tick", "2"});
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  ASSERT_TRUE(Tick(*dut, 1).ok());
  const auto answer = Tick(*dut, 2);
  ASSERT_FALSE(answer.ok());
  EXPECT_EQ(answer.error().message.rfind("dut sent a bad message (malformed", 0), 0u)
      << answer.error().message;
  EXPECT_EQ(Metric(*dut, "link_rx_malformed"), 1.0);
  // The failure sticks with its kind: every later poll reports the same malformed message.
  const auto again = dut->PollCommand();
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(LinkErrorKindOf(again.error()), LinkErrorKind::kMalformed);
}

TEST_F(ProcessDutRealtimeTest, RequestingAnOldTickAgainIsRefused) {
  auto dut = Start();
  ASSERT_NE(dut, nullptr);
  SendHoverReference(*dut);
  ASSERT_TRUE(Tick(*dut, 1).ok());
  dut->RequestStep(1, kTickNs);
  const auto answer = dut->PollCommand();
  ASSERT_FALSE(answer.ok());
  EXPECT_EQ(answer.error().message, "tick 1 requested after tick 1");
}

TEST(ProcessDutPacingTest, LockstepMeasuresNothingAndRefusesRealTimeRequests) {
  rig::EmulatedBus bus;
  ProcessDutOptions options;
  options.dut_emu_path = ::hilrig::test_support::BinDir() + "/dut_emu";
  const rig::SteadyClock wall_clock;
  options.wall_clock = &wall_clock;  // a clock alone does not make the port real time
  auto dut = ProcessDut::Launch(HoverFirmware(), bus.Connect("dut"), kControlPeriodS, options);
  ASSERT_TRUE(dut.ok()) << dut.error().message;
  ASSERT_TRUE(dut.value()->Step(1, kTickNs).ok());
  EXPECT_TRUE(dut.value()->response_latencies().empty());
  EXPECT_EQ(Metric(*dut.value(), "link_commands_superseded"), -1.0);  // real time only
  dut.value()->RequestStep(2, 2 * kTickNs);
  const auto answer = dut.value()->PollCommand();
  ASSERT_FALSE(answer.ok());
  EXPECT_NE(answer.error().message.find("ProcessDutOptions::pacing"), std::string::npos)
      << answer.error().message;
}

TEST(ProcessDutPacingTest, RealTimeNeedsAWallClock) {
  ProcessDutOptions options;
  options.pacing = DutPacing::kRealtime;
  const auto refused = ValidateProcessDutOptions(options);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("needs a wall clock"), std::string::npos)
      << refused.error().message;
}

}  // namespace
}  // namespace hilrig::host
