// dut_link/serial_session.h driven as a runner drives it, over framed LinkMessages from
// libprotobuf, with dut_fw's controller behind it (dut_fw/dut_core_controller.h): the handshake
// and its refusals, the firmware it decodes compared with the host's for a shipped scene, steps
// compared with a DutCore driven directly, and the line's faults.
#include "dut_link/serial_session.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "dut_fw/dut_core_controller.h"
#include "dut_fw/sensor_node.h"
#include "host/dut/firmware_config.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_messages.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "tests/support/serial_dut_fakes.h"
#include "tests/support/serial_step_script.h"
#include "tests/support/test_paths.h"

namespace hilrig::dut_fw {
namespace {

using dut_link::kBridgeGapNs;
using dut_link::SerialDutCounterValues;
using dut_link::SerialDutPhase;
using dut_link::SerialDutSession;
using dut_link::TargetDescription;

// The balloon grasp scene's firmware, its tactile front end calibrated (once per process).
const host::DutFirmware& BalloonFirmware() {
  static const host::DutFirmware firmware = [] {
    auto spec = host::LoadScenario(::hilrig::test_support::SourceDir() +
                                   "/scenarios/balloon_grasp.textproto");
    EXPECT_TRUE(spec.ok()) << spec.error().message;
    spec.value().mutable_models()->mutable_tactile()->set_field_fidelity("map:8");
    host::ScenarioConfig config = host::ResolveScenario(spec.value(), std::nullopt);
    const auto loaded = host::LoadTactileCalibration(config);
    EXPECT_TRUE(loaded.ok()) << loaded.error().message;
    return host::FirmwareFor(config);
  }();
  return firmware;
}

class SerialDutSessionTest : public ::testing::Test {
 protected:
  void Send(const proto::LinkMessage& message) { SendBytes(LineFrame(message)); }
  void SendBytes(const std::vector<std::uint8_t>& bytes) {
    for (const std::uint8_t byte : bytes) session_.OnLinkByte(byte);
  }
  // The one message the session answered with.
  proto::LinkMessage Answer() {
    std::vector<proto::LinkMessage> answers = sink_.Take();
    EXPECT_EQ(answers.size(), 1u);
    return answers.empty() ? proto::LinkMessage() : answers.front();
  }
  void Start(const host::DutFirmware& firmware) {
    Send(Hello());
    ASSERT_TRUE(Answer().has_hello());
    Send(Config(firmware));
    ASSERT_TRUE(Answer().has_target_info());
  }
  proto::SerialCommand Step(const TickInputs& in) {
    bridge_.bytes.insert(bridge_.bytes.end(), in.bridge.begin(), in.bridge.end());
    Send(in.step);
    const proto::LinkMessage answer = Answer();
    EXPECT_TRUE(answer.has_serial_command()) << answer.DebugString();
    return answer.serial_command();
  }

  RecordingSink sink_;
  QueueByteSource bridge_;
  SteppingClock clock_;
  SteppingCycleCounter cycles_;
  TargetDescription target_{"dut_fw test", "fake board", 168'000'000, 40'000, 9'000, 100'000, {}};
  DutCoreController<double> controller_;
  SerialDutSession session_{controller_, sink_, bridge_, clock_, cycles_, target_};
};

TEST_F(SerialDutSessionTest, AnswersHelloThenConfigWithTargetInfo) {
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
  Send(Hello());
  const proto::LinkMessage hello = Answer();
  ASSERT_TRUE(hello.has_hello());
  EXPECT_EQ(hello.hello().role(), proto::Hello::DUT);
  EXPECT_EQ(hello.hello().header().protocol_version(), host::kHilLinkProtocolVersion);
  EXPECT_EQ(hello.hello().name(), "dut_fw test");
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitConfig);

  Send(Config(BalloonFirmware()));
  const proto::LinkMessage info = Answer();
  ASSERT_TRUE(info.has_target_info()) << info.DebugString();
  EXPECT_EQ(info.target_info().board(), "fake board");
  EXPECT_EQ(info.target_info().core_clock_hz(), 168'000'000u);
  EXPECT_EQ(info.target_info().flash_used_bytes(), 40'000u);
  EXPECT_EQ(info.target_info().ram_used_bytes(), 9'000u);
  EXPECT_EQ(info.target_info().stack_bytes(), 100'000u);
  EXPECT_EQ(info.target_info().header().sequence(), 1u);
  EXPECT_EQ(session_.phase(), SerialDutPhase::kRunning);
  ASSERT_NE(controller_.core(), nullptr);
  EXPECT_TRUE(controller_.core()->has_tactile());
}

TEST_F(SerialDutSessionTest, AnotherVersionIsAnsweredByByeWithTheReason) {
  Send(Hello(host::kHilLinkProtocolVersion + 1));
  const proto::LinkMessage bye = Answer();
  ASSERT_TRUE(bye.has_bye());
  EXPECT_TRUE(bye.bye().error());
  EXPECT_EQ(bye.bye().reason(), "protocol version 2, this DUT speaks 1");
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
  Send(Config(BalloonFirmware()));  // no configuration without a hello
  EXPECT_TRUE(Answer().has_bye());
  EXPECT_EQ(controller_.core(), nullptr);
}

TEST_F(SerialDutSessionTest, AHelloFromAnotherDutIsNotAnswered) {
  Send(Hello(host::kHilLinkProtocolVersion, proto::Hello::DUT));
  EXPECT_TRUE(sink_.Take().empty());
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
}

TEST_F(SerialDutSessionTest, RefusesABadConfigWithByeAndTheReason) {
  struct Case {
    const char* what;
    void (*spoil)(proto::DutConfig&);
    const char* reason;
  };
  const Case cases[] = {
      {"five nodes",
       [](proto::DutConfig& c) { c.mutable_tactile()->mutable_nodes()->RemoveLast(); },
       "tactile firmware must have exactly 6 nodes"},
      {"eight matrix values",
       [](proto::DutConfig& c) {
         c.mutable_tactile()
             ->mutable_nodes(2)
             ->mutable_rotation_body_from_sensor()
             ->mutable_row_major()
             ->RemoveLast();
       },
       "tactile node matrix without 9 values"},
      {"node id twice",
       [](proto::DutConfig& c) { c.mutable_tactile()->mutable_nodes(4)->set_node_id(1); },
       "tactile node ids must be 1..6, each used once"},
      {"chip gain", [](proto::DutConfig& c) { c.mutable_tactile()->set_chip_gain_sel(8); },
       "tactile firmware with an invalid chip setting"},
      {"zero period", [](proto::DutConfig& c) { c.set_control_period_s(0); },
       "dut config control period must be positive and finite"},
      {"no grasp", [](proto::DutConfig& c) { c.clear_grasp(); },
       "dut config without flight or grasp firmware"},
      {"nan mass", [](proto::DutConfig& c) { c.mutable_flight()->set_position_mass_kg(NAN); },
       "dut config with a number that is not finite"},
      {"no zeroing", [](proto::DutConfig& c) { c.mutable_tactile()->set_zeroing_samples(0); },
       "tactile zeroing_samples and age limits must be positive"},
      {"long average",
       [](proto::DutConfig& c) { c.mutable_tactile()->set_force_average_samples(17); },
       "tactile force_average_samples must be at most 16"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Send(Hello());
    ASSERT_TRUE(Answer().has_hello());
    proto::LinkMessage config = Config(BalloonFirmware());
    c.spoil(*config.mutable_config());
    Send(config);
    const proto::LinkMessage bye = Answer();
    ASSERT_TRUE(bye.has_bye());
    EXPECT_TRUE(bye.bye().error());
    EXPECT_EQ(bye.bye().reason(), c.reason);
    EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
    EXPECT_EQ(controller_.core(), nullptr);
  }
}

// Every field the host's codec carries comes out of the DUT's decoding as the host had it: the
// decoded parameters, sent through the host's encoder again, give the very same bytes.
TEST(SerialDutConfigTest, DecodesTheShippedSceneFirmwareExactlyAsTheHostHasIt) {
  const host::DutFirmware& firmware = BalloonFirmware();
  ASSERT_TRUE(firmware.tactile.has_value());
  host::DutFirmware without_tactile = firmware;
  without_tactile.tactile.reset();
  without_tactile.external_force_in_position_loop = !firmware.external_force_in_position_loop;
  for (const host::DutFirmware* sent :
       {&firmware, static_cast<const host::DutFirmware*>(&without_tactile)}) {
    const std::string bytes = host::ToDutConfig(*sent, kPeriodS).SerializeAsString();
    DutConfigOnTarget<double> decoded;
    ASSERT_EQ(
        DecodeDutConfig(
            std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), decoded),
        ConfigRefusal::kNone);
    EXPECT_EQ(decoded.control_period_s, kPeriodS);
    EXPECT_EQ(decoded.params.tactile.has_value(), sent->tactile.has_value());
    EXPECT_EQ(host::ToDutConfig(decoded.params, decoded.control_period_s).SerializeAsString(),
              bytes);
    proto::DutConfig parsed;
    ASSERT_TRUE(parsed.ParseFromString(bytes));
    const auto host_setup = host::FromDutConfig(parsed);
    ASSERT_TRUE(host_setup.ok()) << host_setup.error().message;
    EXPECT_EQ(host::ToDutConfig(host_setup.value().firmware, kPeriodS).SerializeAsString(), bytes);
  }
}

// A runner that does not send force_average_samples (zero on the wire) gets a DUT that does not
// filter, on both readers of the message.
TEST(SerialDutConfigTest, AnAbsentForceAverageIsNoFilter) {
  proto::DutConfig config = host::ToDutConfig(BalloonFirmware(), kPeriodS);
  config.mutable_tactile()->clear_force_average_samples();
  const std::string bytes = config.SerializeAsString();
  DutConfigOnTarget<double> decoded;
  ASSERT_EQ(
      DecodeDutConfig(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                      decoded),
      ConfigRefusal::kNone);
  ASSERT_TRUE(decoded.params.tactile.has_value());
  EXPECT_EQ(decoded.params.tactile->force_average_samples, 1u);
  const auto host_setup = host::FromDutConfig(config);
  ASSERT_TRUE(host_setup.ok()) << host_setup.error().message;
  EXPECT_EQ(host_setup.value().firmware.tactile->force_average_samples, 1u);
}

// A field the message leaves out is zero on the DUT as on the host, not the struct's default.
TEST(SerialDutConfigTest, AnAbsentFieldIsZeroAsTheHostReadsIt) {
  proto::DutConfig config = host::ToDutConfig(BalloonFirmware(), kPeriodS);
  config.mutable_flight()->clear_estimator_gravity_m_s2();                    // default 9.81
  config.mutable_grasp()->clear_closed_angle_rad();                           // default 1.6
  config.mutable_tactile()->mutable_nodes(0)->clear_contact_normal_sensor();  // default UnitZ
  const std::string bytes = config.SerializeAsString();
  DutConfigOnTarget<double> decoded;
  DecodeDutConfig(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                  decoded);
  EXPECT_EQ(decoded.params.flight.estimator.gravity_m_s2, 0.0);
  EXPECT_EQ(decoded.params.grasp.closed_angle_rad, 0.0);
  EXPECT_TRUE(decoded.params.tactile->nodes[0].contact_normal_sensor.isZero());
}

TEST_F(SerialDutSessionTest, StepsAsADutCoreDrivenDirectly) {
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  bool pad_force_seen = false;
  for (std::uint64_t tick = 0; tick < 400; ++tick) {
    SCOPED_TRACE(tick);
    const proto::SerialCommand command = Step(InputsAt(tick));
    const DutCoreOutput<double> out = direct.Step(tick);
    ExpectCommandIs(command, out, tick);
    pad_force_seen = pad_force_seen || command.tactile_force_sensor_n_size() != 0;
    if (HasFailure()) return;
  }
  const TactileProcessorState<double>& tactile = controller_.core()->tactile_state();
  EXPECT_EQ(tactile.reference_samples, 100u);
  for (const auto& node : tactile.nodes) EXPECT_EQ(node.samples, 100u);
  EXPECT_TRUE(pad_force_seen) << "the bridge samples never reached the pads' forces";
  EXPECT_TRUE(bridge_.bytes.empty());
  EXPECT_EQ(session_.counters().bridge_frames, 100u * 7u);
  EXPECT_EQ(session_.counters().bridge_bytes_missing, 0u);
}

TEST_F(SerialDutSessionTest, ARepeatedTickIsAnsweredWithoutSteppingAgain) {
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  for (std::uint64_t tick = 0; tick < 5; ++tick) Step(InputsAt(tick));
  for (std::uint64_t tick = 0; tick < 5; ++tick) direct.Step(tick);
  const TickInputs five = InputsAt(5);
  const proto::SerialCommand first = Step(five);
  Send(five.step);  // the answer was lost: the runner asks again
  const proto::LinkMessage again = Answer();
  ASSERT_TRUE(again.has_serial_command());
  EXPECT_EQ(again.serial_command().counters().steps_repeated(), 1u);
  ExpectCommandIs(again.serial_command(), direct.Step(5), 5);
  // Stepping twice would have shown in the next tick's output.
  ExpectCommandIs(Step(InputsAt(6)), direct.Step(6), 6);
  // A tick that never came is counted.
  const proto::SerialCommand eight = Step(InputsAt(8));
  ExpectCommandIs(eight, direct.Step(8), 8);
  EXPECT_EQ(eight.counters().steps_skipped(), 1u);
  EXPECT_EQ(session_.counters().steps_repeated, 1u);
}

TEST_F(SerialDutSessionTest, ByeEndsTheRunAndANewHelloStartsAnother) {
  Start(BalloonFirmware());
  Step(InputsAt(0));
  Send(Bye());
  EXPECT_TRUE(sink_.Take().empty());
  EXPECT_EQ(session_.phase(), SerialDutPhase::kAwaitHello);
  Send(InputsAt(1).step);
  const proto::LinkMessage refused = Answer();
  ASSERT_TRUE(refused.has_bye());
  EXPECT_EQ(refused.bye().reason(), "serial step before an accepted dut config");

  bridge_.bytes.clear();
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  for (std::uint64_t tick = 0; tick < 3; ++tick) {
    ExpectCommandIs(Step(InputsAt(tick)), direct.Step(tick), tick);
  }
}

TEST_F(SerialDutSessionTest, AShortBridgeIsCountedAfterTheGapAndTheStepGoesAhead) {
  Start(BalloonFirmware());
  TickInputs in = InputsAt(0);
  in.step.mutable_serial_step()->set_bridge_bytes(std::uint32_t(in.bridge.size() + 3));
  const int reads_before = clock_.reads;
  const proto::SerialCommand command = Step(in);
  EXPECT_EQ(command.answers_tick(), 0u);
  EXPECT_EQ(command.counters().bridge_bytes_missing(), 3u);
  EXPECT_EQ(command.counters().bridge_frames(), 7u);
  // The wait is bounded by the DUT's clock: kBridgeGapNs of it, read 1 ms at a time.
  EXPECT_EQ(clock_.reads - reads_before, int(kBridgeGapNs / clock_.step_ns) + 1);

  // In a real-time step the DUT takes what is there and does not wait.
  TickInputs realtime = InputsAt(1);
  realtime.step.mutable_serial_step()->set_bridge_bytes(50);
  realtime.step.mutable_serial_step()->set_realtime(true);
  const int reads_realtime = clock_.reads;
  EXPECT_EQ(Step(realtime).answers_tick(), 1u);
  EXPECT_EQ(clock_.reads, reads_realtime);
  EXPECT_EQ(session_.counters().bridge_bytes_missing, 3u);
}

TEST_F(SerialDutSessionTest, GarbageOnTheBridgeIsCountedAndTheFramesAfterItTaken) {
  Start(BalloonFirmware());
  TickInputs in = InputsAt(0);
  const std::vector<std::uint8_t> garbage = {
      0xAA, 0x55, 0x01, 0x01, 0x08, 1, 2,
      3,    4,    5,    6,    7,    8, 0x00};  // a sample frame with a bad CRC-8
  in.bridge.insert(in.bridge.begin(), garbage.begin(), garbage.end());
  in.step.mutable_serial_step()->set_bridge_bytes(std::uint32_t(in.bridge.size()));
  const proto::SerialCommand command = Step(in);
  EXPECT_EQ(command.counters().bridge_bad_frames(), 1u);
  EXPECT_EQ(command.counters().bridge_frames(), 7u);
}

TEST_F(SerialDutSessionTest, GarbageFlippedAndLostBytesOnTheLinkAreCountedAndResynced) {
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  const auto received_before = session_.counters().frames_received;

  // Garbage before a frame (the delimiter ends it): the frame that follows is answered.
  SendBytes({0x13, 0x37, 0xFF, 0x00});
  ExpectCommandIs(Step(InputsAt(0)), direct.Step(0), 0);

  // A flipped bit: the frame is dropped, not answered; the runner's retry is.
  TickInputs one = InputsAt(1);
  std::vector<std::uint8_t> flipped = LineFrame(one.step);
  flipped[flipped.size() / 2] ^= 0x10;
  bridge_.bytes.insert(bridge_.bytes.end(), one.bridge.begin(), one.bridge.end());
  SendBytes(flipped);
  EXPECT_TRUE(sink_.Take().empty());
  Send(one.step);
  const proto::LinkMessage retried = Answer();
  ExpectCommandIs(retried.serial_command(), direct.Step(1), 1);

  // A lost byte: dropped too, and the line is in step again at the next frame.
  std::vector<std::uint8_t> lost = LineFrame(InputsAt(2).step);
  lost.erase(lost.begin() + 5);
  SendBytes(lost);
  EXPECT_TRUE(sink_.Take().empty());
  const proto::SerialCommand two = Step(InputsAt(2));
  ExpectCommandIs(two, direct.Step(2), 2);

  const SerialDutCounterValues counters = session_.counters();
  EXPECT_EQ(counters.frames_received - received_before, 3u);
  EXPECT_EQ(counters.frames_bad_checksum + counters.frames_malformed, 3u);
  EXPECT_EQ(two.counters().frames_bad_checksum(), counters.frames_bad_checksum);
  EXPECT_EQ(two.counters().frames_malformed(), counters.frames_malformed);
}

TEST_F(SerialDutSessionTest, AStepThatDoesNotParseChangesNothing) {
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  TickInputs bad = InputsAt(0);
  bad.step.mutable_serial_step()->mutable_inputs(0)->mutable_imu()->add_gyro_accel(1.f);  // 7
  Send(bad.step);
  EXPECT_TRUE(sink_.Take().empty());
  EXPECT_EQ(session_.counters().frames_malformed, 1u);
  ExpectCommandIs(Step(InputsAt(0)), direct.Step(0), 0);
}

TEST_F(SerialDutSessionTest, WorkCyclesCountTheStepNotTheBridgeWait) {
  cycles_.step = 10;  // every read advances the counter by 10
  Start(BalloonFirmware());
  TickInputs in = InputsAt(0);
  in.step.mutable_serial_step()->set_bridge_bytes(std::uint32_t(in.bridge.size() + 1));
  const proto::SerialCommand command = Step(in);
  // Counted: frame to inputs applied, each bridge byte, step to encoding; not the wait.
  EXPECT_EQ(command.work_cycles(), 10u * (2 + in.bridge.size()));
}

TEST_F(SerialDutSessionTest, AnOlderTickIsNeitherAnsweredNorStepped) {
  Start(BalloonFirmware());
  DirectDut<double> direct(BalloonFirmware());
  for (std::uint64_t tick = 0; tick < 4; ++tick) {
    ExpectCommandIs(Step(InputsAt(tick)), direct.Step(tick), tick);
  }
  Send(InputsAt(1).step);  // a stale copy, overtaken by later ticks
  EXPECT_TRUE(sink_.Take().empty());
  ExpectCommandIs(Step(InputsAt(4)), direct.Step(4), 4);
}

TEST_F(SerialDutSessionTest, AConfigSentAgainIsAnsweredAgainWithAFreshCore) {
  Start(BalloonFirmware());
  Step(InputsAt(0));
  Send(Config(BalloonFirmware()));  // the runner did not see the TargetInfo and sent it again
  EXPECT_TRUE(Answer().has_target_info());
  DirectDut<double> direct(BalloonFirmware());
  ExpectCommandIs(Step(InputsAt(0)), direct.Step(0), 0);
}

TEST_F(SerialDutSessionTest, ReportsThePlatformsReceiveLosses) {
  Start(BalloonFirmware());
  session_.SetReceiveLosses(2, 5);
  const proto::SerialCommand command = Step(InputsAt(0));
  EXPECT_EQ(command.counters().uart_overruns(), 2u);
  EXPECT_EQ(command.counters().rx_ring_drops(), 5u);
  session_.SetReceiveLosses(2, 6);
  EXPECT_EQ(Step(InputsAt(1)).counters().rx_ring_drops(), 6u);
}

}  // namespace
}  // namespace hilrig::dut_fw
