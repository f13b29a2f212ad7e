// The dut_emu server in a thread, with the test playing the runner on real loopback sockets.
// Every wait is bounded.
#include "dut_emu/dut_emu_server.h"

#include <gtest/gtest.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <limits>
#include <sstream>
#include <thread>

#include "host/dut/firmware_config.h"
#include "host/dut/in_process_dut.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_link_socket.h"
#include "rig/emulated_bus.h"
#include "tests/support/full_listener.h"

namespace hilrig::dut_emu {
namespace {

using host::LinkReceived;
using host::LinkReceiveStatus;

constexpr int kWaitMs = 5000;
constexpr double kControlPeriodS = 1e-3;

host::DutFirmware HoverFirmware() {
  return host::DutFirmware{
      host::FirmwareParamsFor(host::QuadrotorParams{}), std::nullopt, {}, true};
}

class DutEmuServerTest : public ::testing::Test {
 protected:
  // Starts the server in a thread and completes the runner's half of the handshake.
  void StartServer(DutEmuOptions options = {}) {
    listener_ = host::LinkListener::Listen().value();
    auto buses = rig::OpenUdpBusGroup(2).value();
    can_ = std::move(buses[0]);
    dut_can_port_ = buses[1]->local_port();
    options.link_port = listener_->port();
    options_ = options;
    server_ = std::thread([this, bus = std::move(buses[1])]() mutable {
      exit_code_ = RunDutEmu(options_, &stop_, log_, std::move(bus));
    });
    link_ = listener_->Accept(kWaitMs).value();
  }

  void Handshake(std::uint32_t version = host::kHilLinkProtocolVersion,
                 const host::DutFirmware& firmware = HoverFirmware()) {
    proto::LinkMessage hello;
    hello.mutable_hello()->set_role(proto::Hello::RUNNER);
    sequencer_.Stamp(hello, 0);
    hello.mutable_hello()->mutable_header()->set_protocol_version(version);
    proto::LinkMessage config;
    *config.mutable_config() = host::ToDutConfig(firmware, kControlPeriodS);
    sequencer_.Stamp(config, 0);
    ASSERT_TRUE(link_->Send(hello).ok());
    ASSERT_TRUE(link_->Send(config).ok());
    const LinkReceived dut_hello = link_->Receive(kWaitMs);
    ASSERT_EQ(dut_hello.status, LinkReceiveStatus::kMessage);
    EXPECT_EQ(dut_hello.message.hello().role(), proto::Hello::DUT);
  }

  proto::LinkMessage StepRequest(std::uint64_t tick, std::int64_t now_ns,
                                 std::vector<std::int64_t> frame_times_ns = {},
                                 bool realtime = false) {
    proto::LinkMessage step;
    step.mutable_step()->set_realtime(realtime);
    step.mutable_step()->set_tick(tick);
    step.mutable_step()->set_now_ns(now_ns);
    step.mutable_step()->set_can_frames_sent(frame_times_ns.size());
    for (std::int64_t time_ns : frame_times_ns) step.mutable_step()->add_can_frame_time_ns(time_ns);
    sequencer_.Stamp(step, now_ns);
    return step;
  }

  int Join() {
    if (server_.joinable()) server_.join();
    return exit_code_;
  }

  ~DutEmuServerTest() override {
    stop_ = true;
    Join();
  }

  DutEmuOptions options_;
  std::atomic<bool> stop_{false};
  std::ostringstream log_;
  int exit_code_ = -1;
  std::unique_ptr<host::LinkListener> listener_;
  std::unique_ptr<host::LinkConnection> link_;
  std::unique_ptr<rig::UdpBus> can_;
  std::uint16_t dut_can_port_ = 0;
  host::LinkSequencer sequencer_;
  std::thread server_;
};

TEST_F(DutEmuServerTest, AnswersEachStepLikeTheInProcessDut) {
  StartServer();
  Handshake();
  rig::EmulatedBus reference_bus;
  host::InProcessDut reference(HoverFirmware(), reference_bus.Connect("dut"), kControlPeriodS);
  const host::VioMessage vio{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()};
  const host::SetpointMessage setpoint{
      {0, 0}, Eigen::Vector3d(0.1, 0, 1.1), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0};
  reference.Send(vio);
  reference.Send(setpoint);
  ASSERT_TRUE(link_->Send(host::ToLink(vio)).ok());
  ASSERT_TRUE(link_->Send(host::ToLink(setpoint)).ok());
  for (std::uint64_t tick = 0; tick < 50; ++tick) {
    const std::int64_t now_ns = static_cast<std::int64_t>(tick) * 1'000'000;
    const host::ImuMessage imu{{tick, now_ns}, {0.01, 0, 0}, {0, 0.2, 9.81}};
    reference.Send(imu);
    ASSERT_TRUE(link_->Send(host::ToLink(imu)).ok());
    ASSERT_TRUE(link_->Send(StepRequest(tick, now_ns)).ok());
    const LinkReceived answer = link_->Receive(kWaitMs);
    ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage) << answer.error;
    const host::ActuatorMessage actual = host::FromLink(answer.message.command()).value();
    const host::ActuatorMessage expected = reference.Step(tick, now_ns).value();
    ASSERT_EQ(actual.answers_sequence, tick);
    for (int i = 0; i < 4; ++i) ASSERT_EQ(actual.rotor_thrust_n[i], expected.rotor_thrust_n[i]);
    ASSERT_EQ(actual.estimated_position_m, expected.estimated_position_m);
  }
  proto::LinkMessage bye;
  bye.mutable_bye()->set_reason("done");
  sequencer_.Stamp(bye, 0);
  ASSERT_TRUE(link_->Send(bye).ok());
  EXPECT_EQ(Join(), kExitOk);
}

TEST_F(DutEmuServerTest, WaitsForTheAnnouncedCanFrames) {
  StartServer();
  Handshake();
  const std::array<std::uint8_t, 3> payload = {1, 2, 3};
  const rig::CanFrame frame = rig::CanFrame::Classic(0x123, payload);
  ASSERT_TRUE(can_->Send(frame, 500'000).ok());
  ASSERT_TRUE(link_->Send(StepRequest(0, 1'000'000, {500'000})).ok());
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage) << log_.str();
  EXPECT_EQ(answer.message.command().answers_sequence(), 0u);
}

// Another process on the host sends a well-formed frame to the DUT's CAN port: it is dropped and
// counted, and the lockstep step that follows gets exactly the frame the runner announced.
TEST_F(DutEmuServerTest, ForgedDatagramIsDroppedAndTheStepGoesOn) {
  StartServer();
  Handshake();
  boost::asio::io_context io;
  boost::asio::ip::udp::socket stranger(
      io, boost::asio::ip::udp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0));
  std::array<std::uint8_t, rig::kUdpCanMaxDatagramBytes> forged{};
  const std::size_t size = rig::EncodeUdpCanDatagram(
      rig::CanFrame::Classic(0x123, std::array<std::uint8_t, 3>{9, 9, 9}), 400'000, forged);
  stranger.send_to(boost::asio::buffer(forged.data(), size),
                   {boost::asio::ip::make_address("127.0.0.1"), dut_can_port_});
  ASSERT_TRUE(
      can_->Send(rig::CanFrame::Classic(0x123, std::array<std::uint8_t, 3>{1, 2, 3}), 500'000)
          .ok());
  ASSERT_TRUE(link_->Send(StepRequest(0, 1'000'000, {500'000})).ok());
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage) << log_.str();
  ASSERT_TRUE(answer.message.has_command()) << answer.message.DebugString();
  EXPECT_EQ(answer.message.command().answers_sequence(), 0u);
  EXPECT_EQ(answer.message.command().can_frames_consumed(), 1u);
  EXPECT_EQ(answer.message.command().can_frames_dropped_foreign(), 1u);
}

TEST_F(DutEmuServerTest, GivesUpWhenAnnouncedFramesNeverCome) {
  DutEmuOptions options;
  options.frame_wait_timeout_ms = 50;
  StartServer(options);
  Handshake();
  ASSERT_TRUE(link_->Send(StepRequest(7, 7'000'000, {6'000'000, 6'500'000})).ok());
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  ASSERT_TRUE(answer.message.has_bye());
  EXPECT_TRUE(answer.message.bye().error());
  EXPECT_EQ(answer.message.bye().reason(), "tick 7: 0 CAN frames arrived, the runner sent 2");
  EXPECT_EQ(Join(), kExitFailed);
}

TEST_F(DutEmuServerTest, CommandSaysWhatTheDutHadConsumed) {
  StartServer();
  Handshake();
  ASSERT_TRUE(link_->Send(StepRequest(0, 1'000'000)).ok());
  const LinkReceived before = link_->Receive(kWaitMs);
  ASSERT_EQ(before.status, LinkReceiveStatus::kMessage) << log_.str();
  const proto::LinkMessage vio = host::ToLink(
      host::VioMessage{{0, 0}, 0, Eigen::Vector3d(0, 0, 1), Eigen::Quaterniond::Identity()});
  ASSERT_TRUE(link_->Send(vio).ok());
  for (std::uint64_t sequence = 0; sequence < 3; ++sequence) {
    ASSERT_TRUE(link_->Send(host::ToLink(host::ImuMessage{{sequence, 1'500'000}})).ok());
  }
  const std::array<std::uint8_t, 2> payload = {4, 5};
  ASSERT_TRUE(can_->Send(rig::CanFrame::Classic(0x321, payload), 1'600'000).ok());
  ASSERT_TRUE(link_->Send(StepRequest(1, 2'000'000, {1'600'000})).ok());
  const LinkReceived after = link_->Receive(kWaitMs);
  ASSERT_EQ(after.status, LinkReceiveStatus::kMessage) << log_.str();

  const proto::ActuatorCommand& first = before.message.command();
  EXPECT_FALSE(first.has_last_imu_sequence());
  EXPECT_FALSE(first.has_last_vio_sequence());
  EXPECT_FALSE(first.has_last_setpoint_sequence());
  EXPECT_EQ(first.can_frames_consumed(), 0u);
  const proto::ActuatorCommand& second = after.message.command();
  ASSERT_TRUE(second.has_last_imu_sequence());
  EXPECT_EQ(second.last_imu_sequence(), 2u);
  ASSERT_TRUE(second.has_last_vio_sequence());
  EXPECT_EQ(second.last_vio_sequence(), 0u);
  EXPECT_FALSE(second.has_last_setpoint_sequence());
  EXPECT_EQ(second.can_frames_consumed(), 1u);
}

TEST_F(DutEmuServerTest, RealtimeStepGoesAheadWithoutFramesThatDoNotCome) {
  StartServer();
  Handshake();
  ASSERT_TRUE(link_->Send(StepRequest(7, 7'000'000, {6'000'000, 6'500'000}, true)).ok());
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage) << log_.str();
  ASSERT_TRUE(answer.message.has_command()) << answer.message.DebugString();
  EXPECT_EQ(answer.message.command().answers_sequence(), 7u);
  EXPECT_EQ(answer.message.command().can_frame_waits_expired(), 1u);
  EXPECT_EQ(answer.message.command().can_frames_consumed(), 0u);
}

TEST_F(DutEmuServerTest, RealtimeFrameThatComesLateReachesALaterStep) {
  StartServer();
  Handshake();
  ASSERT_TRUE(link_->Send(StepRequest(1, 1'000'000, {900'000}, true)).ok());
  const LinkReceived first = link_->Receive(kWaitMs);
  ASSERT_EQ(first.status, LinkReceiveStatus::kMessage) << log_.str();
  const std::array<std::uint8_t, 1> payload = {9};
  ASSERT_TRUE(can_->Send(rig::CanFrame::Classic(0x55, payload), 900'000).ok());
  // Later requests announce no frame of their own; the DUT takes the late one anyway (the loop
  // only covers the datagram still being on its way).
  std::uint64_t consumed = 0;
  for (std::uint64_t tick = 2; tick < 2000 && consumed == 0; ++tick) {
    ASSERT_TRUE(
        link_->Send(StepRequest(tick, static_cast<std::int64_t>(tick) * 1'000'000, {}, true)).ok());
    const LinkReceived answer = link_->Receive(kWaitMs);
    ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage) << log_.str();
    consumed = answer.message.command().can_frames_consumed();
  }
  EXPECT_EQ(first.message.command().can_frame_waits_expired(), 1u);
  EXPECT_EQ(consumed, 1u);
}

// A DUT that fell behind finds later steps' frames already in its socket: each step still
// consumes only the frames it announces, without waiting for any.
TEST_F(DutEmuServerTest, RealtimeFramesAheadOfTheirRequestWaitForIt) {
  StartServer();
  Handshake();
  const std::array<std::uint8_t, 1> payload = {9};
  ASSERT_TRUE(can_->Send(rig::CanFrame::Classic(0x55, payload), 900'000).ok());
  ASSERT_TRUE(can_->Send(rig::CanFrame::Classic(0x56, payload), 1'900'000).ok());
  ASSERT_TRUE(link_->Send(StepRequest(1, 1'000'000, {900'000}, true)).ok());
  ASSERT_TRUE(link_->Send(StepRequest(2, 2'000'000, {1'900'000}, true)).ok());
  const LinkReceived first = link_->Receive(kWaitMs);
  const LinkReceived second = link_->Receive(kWaitMs);
  ASSERT_EQ(first.status, LinkReceiveStatus::kMessage) << log_.str();
  ASSERT_EQ(second.status, LinkReceiveStatus::kMessage) << log_.str();
  EXPECT_EQ(first.message.command().can_frames_consumed(), 1u);
  EXPECT_EQ(second.message.command().can_frames_consumed(), 2u);
  EXPECT_EQ(second.message.command().can_frame_waits_expired(), 0u);
}

TEST_F(DutEmuServerTest, RefusesARunnerOfAnotherProtocolVersion) {
  StartServer();
  Handshake(99);
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  ASSERT_TRUE(answer.message.has_bye());
  EXPECT_NE(answer.message.bye().reason().find("bad_version"), std::string::npos)
      << answer.message.bye().reason();
  EXPECT_EQ(Join(), kExitFailed);
}

TEST_F(DutEmuServerTest, RefusesAFirmwareWithANanNamingTheField) {
  StartServer();
  host::DutFirmware firmware = HoverFirmware();
  firmware.flight.position.mass_kg = std::numeric_limits<double>::quiet_NaN();
  Handshake(host::kHilLinkProtocolVersion, firmware);
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  ASSERT_TRUE(answer.message.has_bye()) << answer.message.DebugString();
  EXPECT_TRUE(answer.message.bye().error());
  EXPECT_EQ(answer.message.bye().reason(),
            "bad firmware configuration: flight.position.mass_kg is nan: must be finite and > 0");
  EXPECT_EQ(Join(), kExitFailed);
}

TEST_F(DutEmuServerTest, GarbageFromTheRunnerEndsTheSessionWithANamedError) {
  StartServer();
  Handshake();
  ASSERT_TRUE(link_->SendBytes(std::string("\x04\x0f\xff\xff\xff", 5)).ok());
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  EXPECT_NE(answer.message.bye().reason().find("malformed"), std::string::npos);
  EXPECT_EQ(Join(), kExitFailed);
}

TEST_F(DutEmuServerTest, StopRequestEndsCleanlyWithABye) {
  StartServer();
  Handshake();
  stop_ = true;
  const LinkReceived answer = link_->Receive(kWaitMs);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  EXPECT_FALSE(answer.message.bye().error());
  EXPECT_EQ(Join(), kExitOk);
}

TEST_F(DutEmuServerTest, RunnerVanishingIsAFailure) {
  StartServer();
  Handshake();
  link_.reset();
  EXPECT_EQ(Join(), kExitFailed);
  EXPECT_NE(log_.str().find("closed the link without a bye"), std::string::npos);
}

TEST_F(DutEmuServerTest, HelloProvesTheLinkToken) {
  DutEmuOptions options;
  options.link_token = host::NewLinkToken().value();
  StartServer(options);
  const LinkReceived hello = link_->Receive(kWaitMs);
  ASSERT_EQ(hello.status, LinkReceiveStatus::kMessage);
  EXPECT_TRUE(host::ProvesLinkToken(*options.link_token, hello.message.hello().token()));
}

// A DUT started by hand with a wrong token hears why the runner hung up.
TEST_F(DutEmuServerTest, RunnerThatRefusesTheDutIsAClearError) {
  StartServer();
  ASSERT_EQ(link_->Receive(kWaitMs).status, LinkReceiveStatus::kMessage);  // the DUT's hello
  proto::LinkMessage bye;
  bye.mutable_bye()->set_error(true);
  bye.mutable_bye()->set_reason("refused: wrong_token");
  sequencer_.Stamp(bye, 0);
  ASSERT_TRUE(link_->Send(bye).ok());
  link_.reset();
  EXPECT_EQ(Join(), kExitFailed);
  EXPECT_NE(log_.str().find("the runner refused the link (refused: wrong_token); the link token "
                            "comes from --token-file or HILRIG_LINK_TOKEN"),
            std::string::npos)
      << log_.str();
}

// Ctrl-C while the runner does not answer the connect ends dut_emu as a stop does once the link
// is up, without waiting out the connect timeout.
TEST(DutEmuConnectTest, AStopRequestWhileTheRunnerDoesNotAnswerEndsCleanly) {
  host::FullListener full;
  DutEmuOptions options;
  options.link_port = full.port();
  options.connect_timeout_ms = 60'000;
  std::atomic<bool> stop{true};
  rig::EmulatedBus bus;
  std::ostringstream log;
  EXPECT_EQ(RunDutEmu(options, &stop, log, bus.Connect("dut")), kExitOk);
  EXPECT_NE(log.str().find("link connect to 127.0.0.1:" + std::to_string(full.port()) + " stopped"),
            std::string::npos)
      << log.str();
}

TEST(DutEmuArgsTest, ParsesTheWrongTickTestHook) {
  const auto options = ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000", "--can", "udp:30000",
                                        "--test-wrong-tick-at-tick", "12"})
                           .value();
  ASSERT_TRUE(options.wrong_tick_at_tick.has_value());
  EXPECT_EQ(*options.wrong_tick_at_tick, 12u);
  EXPECT_FALSE(options.silent_at_tick.has_value());
}

TEST(DutEmuArgsTest, ParsesLinkAndUdpBus) {
  const auto options =
      ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000", "--can", "udp:30000"}).value();
  EXPECT_EQ(options.link_host, "127.0.0.1");
  EXPECT_EQ(options.link_port, 4000);
  EXPECT_EQ(options.can.scheme, rig::CanBusUri::Scheme::kUdp);
  EXPECT_EQ(options.can.udp.base_port, 30000);
  EXPECT_EQ(options.can.udp.node_index, 1u);
  EXPECT_EQ(options.can.udp.node_count, 2u);
}

TEST(DutEmuArgsTest, ParsesATokenFile) {
  const auto options = ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000", "--can", "udp:30000",
                                        "--token-file", "/run/dut/token"})
                           .value();
  EXPECT_EQ(options.token_file, "/run/dut/token");
}

TEST(DutEmuArgsTest, ParsesEveryCanBusUri) {
  const auto options =
      ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000", "--can", "gs_usb:ABC"}).value();
  EXPECT_EQ(options.can.scheme, rig::CanBusUri::Scheme::kGsUsb);
  EXPECT_EQ(options.can.usb_serial, "ABC");
}

TEST(DutEmuArgsTest, RefusesBadArguments) {
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000"}).ok());  // no --can
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:0", "--can", "udp:1"}).ok());
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--link", "nohost", "--can", "udp:1"}).ok());
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--bogus", "1"}).ok());
  // Named for what it is, with or without a value after it.
  EXPECT_EQ(ParseDutEmuArgs({"dut_emu", "--bogus"}).error().message, "unknown option --bogus");
  EXPECT_EQ(ParseDutEmuArgs({"dut_emu", "--link"}).error().message, "--link needs a value");
  EXPECT_EQ(ParseDutEmuArgs({"dut_emu", "--link", "127.0.0.1:4000", "--can", "serial:/dev/ttyUSB0"})
                .error()
                .message,
            "CAN bus \"serial:/dev/ttyUSB0\": unknown scheme \"serial\"; expected emulated, "
            "udp:BASE_PORT[:INDEX[:COUNT]], socketcan:IFACE or gs_usb[:SERIAL]");
}

}  // namespace
}  // namespace hilrig::dut_emu
