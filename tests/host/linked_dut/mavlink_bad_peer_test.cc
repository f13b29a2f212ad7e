// A MAVLink DUT that breaks the contract (tests/host/linked_dut/mavlink_bad_peer.cc) stops the run
// with an error that names what it did, within the watchdog, and never hangs it: silent, garbage,
// outputs that are not numbers, answers twice or at a time never asked, a hang-up, refused
// commands (the grasp among them), no heartbeat at all.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/dut/firmware_config.h"
#include "host/linked_dut/mavlink_dut.h"
#include "rig/clock.h"
#include "rig/emulated_bus.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

constexpr double kControlPeriodS = 1e-3;

struct Outcome {
  std::optional<rig::Error> start_error;
  std::optional<rig::Error> step_error;
  std::uint64_t failed_at_tick = 0;
  double seconds = 0;
  std::optional<ActuatorMessage> last_command;
  std::vector<rig::Metric> metrics;

  double Metric(const std::string& name) const {
    for (const rig::Metric& metric : metrics) {
      if (metric.name == name) return metric.value;
    }
    return -1;
  }
};

// Starts the bad peer in `mode` and steps it at 1 kHz for up to 2 s of the run's time, grasping
// from the start when `grasp` says so. At tick 10 a sensor puts a classic and a CAN FD frame on
// the bus.
Outcome Fly(const std::string& mode, bool grasp = false) {
  rig::EmulatedBus bus;
  const rig::SteadyClock clock;
  MavlinkDutPortOptions options;
  options.link.dut_emu_path = ::hilrig::test_support::BinDir() + "/mavlink_bad_peer";
  options.link.extra_args = {"--mode", mode};
  options.link.start_timeout_s = 1;
  options.link.command_timeout_s = 1.5;
  options.session.answer_timeout_s = 0.5;
  options.session.clock = &clock;
  MavlinkDut dut(DutFirmware{FirmwareParamsFor(QuadrotorParams{}), std::nullopt, {}, true},
                 bus.Connect("dut"), kControlPeriodS, options);
  const std::unique_ptr<rig::CanBus> sensor = bus.Connect("sensor");
  Outcome outcome;
  const auto begin = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  };
  if (auto started = dut.Start(); !started) {
    outcome.start_error = started.error();
    outcome.seconds = elapsed();
    return outcome;
  }
  SetpointMessage setpoint;
  setpoint.position_m = Eigen::Vector3d(0, 0, 1);
  setpoint.grasp_regulate = grasp;
  setpoint.grasp_force_n = grasp ? 2.0 : 0.0;
  dut.Send(setpoint);
  for (std::uint64_t tick = 1; tick <= 2000; ++tick) {
    const std::int64_t now_ns = std::int64_t(tick) * 1'000'000;
    dut.Send(ImuMessage{{tick - 1, now_ns},
                        Eigen::Vector3d(0.001 * double(tick % 7), 0, 0),
                        Eigen::Vector3d(0, 0, 9.81)});
    if (tick == 10) {
      const std::array<std::uint8_t, 2> payload = {7, 8};
      EXPECT_TRUE(sensor->Send(rig::CanFrame::Classic(0x101, payload), now_ns));
      EXPECT_TRUE(sensor->Send(rig::CanFrame::Fd(0x102, payload, false), now_ns));
    }
    auto command = dut.Step(tick, now_ns);
    if (!command) {
      outcome.step_error = command.error();
      outcome.failed_at_tick = tick;
      break;
    }
    outcome.last_command = command.value();
  }
  outcome.seconds = elapsed();
  outcome.metrics = dut.link_metrics();
  dut.Stop();
  return outcome;
}

void ExpectStepFails(const std::string& mode, const std::string& says, bool grasp = false) {
  const Outcome outcome = Fly(mode, grasp);
  EXPECT_FALSE(outcome.start_error) << mode << ": " << outcome.start_error->message;
  ASSERT_TRUE(outcome.step_error) << mode << ": flew 2000 ticks";
  EXPECT_NE(outcome.step_error->message.find(says), std::string::npos)
      << mode << ": " << outcome.step_error->message;
  EXPECT_LT(outcome.seconds, 3.0) << mode;
}

TEST(MavlinkBadPeerTest, ASilentPeerTripsTheWatchdog) {
  ExpectStepFails("silent", "did not answer tick 4 within 0.5 s");
}

TEST(MavlinkBadPeerTest, GarbageIsNoAnswer) {
  ExpectStepFails("garbage", "that were no MAVLink frame the rig could check");
}

TEST(MavlinkBadPeerTest, AnOutputThatIsNotANumberIsNamed) {
  ExpectStepFails("nan", "non-finite actuator output 2");
}

TEST(MavlinkBadPeerTest, ATwinAnswerIsAnAnswerNobodyAskedFor) {
  ExpectStepFails("twice", "which no HIL_SENSOR asked for");
}

TEST(MavlinkBadPeerTest, AnAnswerAtAnotherTimeIsNamed) {
  ExpectStepFails("wrong-time", "the dut answered time 4001 us");
}

TEST(MavlinkBadPeerTest, AHangUpIsNamedByThePeersExit) {
  ExpectStepFails("disconnect", "exited with status 3");
}

// Refusals are asked again once a second (PX4 refuses to arm at first); for longer than the
// command timeout, they stop the run.
TEST(MavlinkBadPeerTest, ACommandRefusedForTooLongIsNamed) {
  ExpectStepFails("refuse",
                  "the dut refused command 176 (MAV_CMD_DO_SET_MODE) for 1.5 s of the run (last "
                  "answer MAV_RESULT 4)");
}

// A flight stack without a gripper cannot fly a grasping scene: the run stops naming the command.
TEST(MavlinkBadPeerTest, AGraspThePeerCannotTakeIsNamed) {
  ExpectStepFails("no-gripper",
                  "the dut refused command 211 (MAV_CMD_DO_GRIPPER) for 1.5 s of the run (last "
                  "answer MAV_RESULT 3)",
                  /*grasp=*/true);
}

// Not a bad peer: one that tells in its estimates what reached it. The tactile frame went as
// CAN_FRAME (the CAN FD one cannot), the grasp as MAV_CMD_DO_GRIPPER with its set-point, and the
// estimates became the command's, in the rig's frames.
TEST(MavlinkBadPeerTest, FramesTheGraspAndTheEstimatesCrossTheLink) {
  const Outcome outcome = Fly("echo", /*grasp=*/true);
  ASSERT_FALSE(outcome.start_error) << outcome.start_error->message;
  ASSERT_FALSE(outcome.step_error) << outcome.step_error->message;
  ASSERT_TRUE(outcome.last_command);
  EXPECT_EQ(outcome.last_command->estimated_position_m, Eigen::Vector3d(2, 1, 3));
  EXPECT_EQ(outcome.last_command->external_force_world_n.y(), 2.0) << "the set-point, north";
  EXPECT_EQ(outcome.last_command->grasp_force_estimate_n, 1.0) << "one CAN_FRAME received";
  EXPECT_EQ(outcome.Metric("mavlink_can_frames_sent"), 1);
  EXPECT_EQ(outcome.Metric("mavlink_can_frames_not_carried"), 1);
  EXPECT_EQ(outcome.Metric("mavlink_estimates_received"), 500) << "one per sensor step";
}

TEST(MavlinkBadPeerTest, APeerWithoutAHeartbeatNeverStarts) {
  const Outcome outcome = Fly("mute");
  ASSERT_TRUE(outcome.start_error);
  EXPECT_NE(outcome.start_error->message.find("sent no heartbeat to the API port"),
            std::string::npos)
      << outcome.start_error->message;
  EXPECT_LT(outcome.seconds, 2.0);
}

}  // namespace
}  // namespace hilrig::host
