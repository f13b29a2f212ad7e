// A MAVLink DUT that breaks the contract (tests/host/linked_dut/mavlink_bad_peer.cc) stops the run
// with an error that names what it did, within the watchdog, and never hangs it: silent, garbage,
// outputs that are not numbers, answers twice or at a time never asked, a hang-up, refused
// commands, no heartbeat at all.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>

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
};

// Starts the bad peer in `mode` and steps it at 1 kHz for up to 2 s of the run's time.
Outcome Fly(const std::string& mode) {
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
  dut.Send(setpoint);
  for (std::uint64_t tick = 1; tick <= 2000; ++tick) {
    const std::int64_t now_ns = std::int64_t(tick) * 1'000'000;
    dut.Send(ImuMessage{{tick - 1, now_ns},
                        Eigen::Vector3d(0.001 * double(tick % 7), 0, 0),
                        Eigen::Vector3d(0, 0, 9.81)});
    if (auto command = dut.Step(tick, now_ns); !command) {
      outcome.step_error = command.error();
      outcome.failed_at_tick = tick;
      break;
    }
  }
  outcome.seconds = elapsed();
  dut.Stop();
  return outcome;
}

void ExpectStepFails(const std::string& mode, const std::string& says) {
  const Outcome outcome = Fly(mode);
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
                  "the dut refused command 176 for 1.5 s of the run (last answer "
                  "MAV_RESULT 4)");
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
