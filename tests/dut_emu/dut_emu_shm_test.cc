// The dut_emu server on the shared-memory link, in a thread, with the test playing the runner on
// the other end of the mapping: no token, and the CAN frames ride in the step requests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <sstream>
#include <thread>

#include "dut_emu/dut_emu_server.h"
#include "host/dut/firmware_config.h"
#include "host/link/dut_config_codec.h"
#include "host/link/hil_link_socket.h"
#include "host/link/shm_byte_stream.h"
#include "rig/udp_bus.h"

namespace hilrig::dut_emu {
namespace {

using host::LinkReceived;
using host::LinkReceiveStatus;

constexpr int kWaitMs = 5000;

std::string Datagram(const rig::CanFrame& frame, std::int64_t time_ns) {
  std::array<std::uint8_t, rig::kUdpCanMaxDatagramBytes> bytes;
  const std::size_t size = rig::EncodeUdpCanDatagram(frame, time_ns, bytes);
  return std::string(reinterpret_cast<const char*>(bytes.data()), size);
}

class DutEmuShmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto stream = host::ShmByteStream::Create();
    ASSERT_TRUE(stream.ok()) << stream.error().message;
    options_ = ParseDutEmuArgs(
                   {"dut_emu", "--link-shm", std::to_string(::dup(stream.value()->shared_fd()))})
                   .value();
    link_ = std::make_unique<host::LinkConnection>(std::move(stream).value(), "dut");
    server_ = std::thread([this] { exit_code_ = RunDutEmu(options_, &stop_, log_); });
    const LinkReceived hello = link_->Receive(kWaitMs);
    ASSERT_EQ(hello.status, LinkReceiveStatus::kMessage) << log_.str();
    EXPECT_TRUE(hello.message.hello().token().empty());
    proto::LinkMessage runner_hello;
    runner_hello.mutable_hello()->set_role(proto::Hello::RUNNER);
    sequencer_.Stamp(runner_hello, 0);
    proto::LinkMessage config;
    *config.mutable_config() = host::ToDutConfig(
        host::DutFirmware{host::FirmwareParamsFor(host::QuadrotorParams{}), std::nullopt, {}, true},
        1e-3);
    sequencer_.Stamp(config, 0);
    ASSERT_TRUE(link_->Send(runner_hello).ok());
    ASSERT_TRUE(link_->Send(config).ok());
  }

  void TearDown() override {
    stop_ = true;
    if (server_.joinable()) server_.join();
  }

  // The answer to a step request that carries `frames` (all stamped `frame_time_ns`), announcing
  // `announced` of them.
  LinkReceived Step(std::uint64_t tick, const std::vector<std::string>& frames,
                    std::size_t announced, std::int64_t frame_time_ns = 500'000) {
    proto::LinkMessage step;
    step.mutable_step()->set_tick(tick);
    step.mutable_step()->set_now_ns(static_cast<std::int64_t>(tick) * 1'000'000);
    step.mutable_step()->set_can_frames_sent(announced);
    for (std::size_t i = 0; i < announced; ++i) {
      step.mutable_step()->add_can_frame_time_ns(frame_time_ns);
    }
    for (const std::string& frame : frames) step.mutable_step()->add_can_frame(frame);
    sequencer_.Stamp(step, step.step().now_ns());
    EXPECT_TRUE(link_->Send(step).ok());
    return link_->Receive(kWaitMs);
  }

  DutEmuOptions options_;
  std::atomic<bool> stop_{false};
  std::ostringstream log_;
  int exit_code_ = -1;
  std::unique_ptr<host::LinkConnection> link_;
  host::LinkSequencer sequencer_;
  std::thread server_;
};

TEST_F(DutEmuShmTest, TakesTheFramesTheStepRequestCarries) {
  const std::array<std::uint8_t, 2> payload = {4, 5};
  const std::string frame = Datagram(rig::CanFrame::Classic(0x321, payload), 400'000);
  const LinkReceived first = Step(1, {frame, frame}, 2);
  ASSERT_EQ(first.status, LinkReceiveStatus::kMessage) << log_.str();
  EXPECT_EQ(first.message.command().can_frames_consumed(), 2u);
  const LinkReceived second = Step(2, {}, 0);
  ASSERT_EQ(second.status, LinkReceiveStatus::kMessage) << log_.str();
  EXPECT_EQ(second.message.command().can_frames_consumed(), 2u);
}

TEST_F(DutEmuShmTest, FramesThatDoNotMatchTheAnnouncementEndTheSession) {
  const std::array<std::uint8_t, 1> payload = {1};
  const LinkReceived answer = Step(1, {Datagram(rig::CanFrame::Classic(0x10, payload), 0)}, 2);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  ASSERT_TRUE(answer.message.has_bye());
  EXPECT_NE(answer.message.bye().reason().find("announces 2 CAN frames but carries 1"),
            std::string::npos)
      << answer.message.bye().reason();
  if (server_.joinable()) server_.join();
  EXPECT_EQ(exit_code_, kExitFailed);
}

TEST_F(DutEmuShmTest, AFrameThatDoesNotDecodeEndsTheSession) {
  const LinkReceived answer = Step(1, {"not a datagram"}, 1);
  ASSERT_EQ(answer.status, LinkReceiveStatus::kMessage);
  ASSERT_TRUE(answer.message.has_bye());
  EXPECT_NE(answer.message.bye().reason().find("bad CAN frame"), std::string::npos);
}

TEST(DutEmuShmArgsTest, ParsesTheSharedMemoryLink) {
  const auto options = ParseDutEmuArgs({"dut_emu", "--link-shm", "7"});
  ASSERT_TRUE(options.ok()) << options.error().message;
  EXPECT_EQ(options.value().link_shm_fd, 7);
  EXPECT_TRUE(options.value().can_in_link);
  const auto with_bus = ParseDutEmuArgs({"dut_emu", "--link-shm", "7", "--can", "socketcan:vcan0"});
  ASSERT_TRUE(with_bus.ok());
  EXPECT_FALSE(with_bus.value().can_in_link);
  EXPECT_EQ(with_bus.value().can.scheme, rig::CanBusUri::Scheme::kSocketCan);
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--link-shm", "-1"}).ok());
  EXPECT_FALSE(ParseDutEmuArgs({"dut_emu", "--link-shm", "x"}).ok());
  EXPECT_FALSE(
      ParseDutEmuArgs({"dut_emu", "--link-shm", "7", "--link", "127.0.0.1:4000", "--can", "udp:1"})
          .ok());
}

}  // namespace
}  // namespace hilrig::dut_emu
