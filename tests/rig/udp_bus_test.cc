#include "rig/udp_bus.h"

#include <gtest/gtest.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace hilrig::rig {
namespace {

namespace asio = boost::asio;
using asio::ip::udp;

constexpr int kMaxPolls = 10'000;

using Datagram = std::vector<std::uint8_t>;

Datagram Encode(const CanFrame& frame, std::int64_t sender_time_ns = 0) {
  std::array<std::uint8_t, kUdpCanMaxDatagramBytes> buffer{};
  const std::size_t size = EncodeUdpCanDatagram(frame, sender_time_ns, buffer);
  return Datagram(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(size));
}

CanFrame Sample() { return CanFrame::Classic(0x123, std::array<std::uint8_t, 3>{1, 2, 3}); }

std::vector<std::unique_ptr<UdpBus>> OpenPair() {
  auto group = OpenUdpBusGroup(2);
  EXPECT_TRUE(group.ok()) << (group.ok() ? "" : group.error().message);
  return group.ok() ? std::move(group).value() : std::vector<std::unique_ptr<UdpBus>>{};
}

// Polls until `count` frames arrived or the budget is spent; every poll is stamped now_ns.
std::vector<TimedCanFrame> ReceiveFrames(CanBus& endpoint, std::size_t count,
                                         std::int64_t now_ns = 0) {
  std::vector<TimedCanFrame> received;
  for (int poll = 0; poll < kMaxPolls && received.size() < count; ++poll) {
    endpoint.Receive(now_ns, received);
    std::this_thread::yield();
  }
  return received;
}

TEST(UdpCanDatagramTest, RoundTripsEveryKindOfFrame) {
  const std::vector<CanFrame> frames = {
      Sample(),
      CanFrame::ClassicExtended(0x1FFFFFFF, std::array<std::uint8_t, 8>{8, 7, 6, 5, 4, 3, 2, 1}),
      CanFrame::Remote(0x7FF, 8, /*extended=*/false),
      CanFrame::Fd(0x100, std::vector<std::uint8_t>(64, 0xEE), /*bitrate_switch=*/true),
      CanFrame::ErrorFrame(0x40, {0, 0x20, 0, 0, 0, 0, 9, 10}),
  };

  for (const CanFrame& frame : frames) {
    const Result<UdpCanDatagram> decoded = DecodeUdpCanDatagram(Encode(frame, -5));

    ASSERT_TRUE(decoded.ok()) << frame << ": " << decoded.error().message;
    EXPECT_EQ(decoded.value().frame, frame);
    EXPECT_EQ(decoded.value().sender_time_ns, -5);
  }
}

TEST(UdpCanDatagramTest, RemoteFrameCarriesNoPayloadOnTheWire) {
  EXPECT_EQ(Encode(CanFrame::Remote(0x7FF, 8, false)).size(), kUdpCanHeaderBytes);
}

struct MalformedCase {
  std::string name;
  Datagram datagram;
};

std::vector<MalformedCase> MalformedCases() {
  const Datagram good = Encode(Sample());
  std::vector<MalformedCase> cases;
  const auto with = [&](std::string name, auto edit) {
    Datagram datagram = good;
    edit(datagram);
    cases.push_back({std::move(name), std::move(datagram)});
  };
  with("empty", [](Datagram& d) { d.clear(); });
  with("short_header", [](Datagram& d) { d.resize(kUdpCanHeaderBytes - 1); });
  with("bad_magic", [](Datagram& d) { d[0] ^= 0xFF; });
  with("bad_version", [](Datagram& d) { d[4] = 2; });
  with("unknown_flag", [](Datagram& d) { d[5] |= 0x80; });
  with("reserved_set", [](Datagram& d) { d[7] = 1; });
  with("payload_short", [](Datagram& d) { d.pop_back(); });
  with("payload_long", [](Datagram& d) { d.push_back(0); });
  with("oversized", [](Datagram& d) { d.resize(kUdpCanMaxDatagramBytes + 1); });
  with("standard_id_too_big", [](Datagram& d) { d[9] = 0x08; });  // id 0x823
  with("classic_length_9", [](Datagram& d) { d[6] = 9; });
  return cases;
}

class UdpCanDatagramMalformedTest : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(UdpCanDatagramMalformedTest, IsRefused) {
  EXPECT_FALSE(DecodeUdpCanDatagram(GetParam().datagram).ok());
}

INSTANTIATE_TEST_SUITE_P(Cases, UdpCanDatagramMalformedTest, ::testing::ValuesIn(MalformedCases()),
                         [](const auto& info) { return info.param.name; });

TEST(UdpBusTest, MalformedDatagramsAreCountedAndDropped) {
  auto pair = OpenPair();
  ASSERT_EQ(pair.size(), 2u);
  asio::io_context io;
  udp::socket stranger(io, udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const udp::endpoint target(asio::ip::make_address("127.0.0.1"), pair[1]->local_port());
  const std::vector<MalformedCase> cases = MalformedCases();

  for (const MalformedCase& bad : cases) stranger.send_to(asio::buffer(bad.datagram), target);
  ASSERT_TRUE(pair[0]->Send(Sample(), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveFrames(*pair[1], 1);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame, Sample());
  EXPECT_EQ(pair[1]->counters().frames_dropped_malformed, cases.size());
  EXPECT_EQ(pair[1]->counters().frames_received, 1u);
}

// Any process on the host can send to a loopback port: a well-formed frame from a port outside the
// bus must not reach the receiver (it would pass for sensor data).
TEST(UdpBusTest, FrameFromOutsideTheBusIsCountedAndDropped) {
  auto pair = OpenPair();
  ASSERT_EQ(pair.size(), 2u);
  asio::io_context io;
  udp::socket stranger(io, udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const udp::endpoint target(asio::ip::make_address("127.0.0.1"), pair[1]->local_port());
  const CanFrame forged = CanFrame::Classic(0x7FF, std::array<std::uint8_t, 2>{0xAA, 0x55});

  stranger.send_to(asio::buffer(Encode(forged)), target);
  ASSERT_TRUE(pair[0]->Send(Sample(), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveFrames(*pair[1], 1);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame, Sample());
  EXPECT_EQ(pair[1]->counters().frames_dropped_foreign, 1u);
  EXPECT_EQ(pair[1]->counters().frames_dropped_malformed, 0u);
  EXPECT_EQ(pair[1]->counters().frames_received, 1u);
}

// The ports come from the kernel's randomness, not from anything another process can read (such
// as the process id): groups opened one after the other in one process land on different ports.
TEST(UdpBusTest, GroupPortsAreNotAFunctionOfTheProcess) {
  std::set<std::uint16_t> base_ports;
  for (int i = 0; i < 4; ++i) base_ports.insert(OpenPair().at(0)->local_port());
  EXPECT_GT(base_ports.size(), 1u);
}

TEST(UdpBusTest, ReceiverStampsFramesWithItsOwnNow) {
  auto pair = OpenPair();
  ASSERT_EQ(pair.size(), 2u);

  ASSERT_TRUE(pair[0]->Send(Sample(), 1'000).ok());
  const std::vector<TimedCanFrame> received = ReceiveFrames(*pair[1], 1, 77'000);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].time_ns, 77'000);
}

TEST(UdpBusTest, BindsLoopbackByDefault) {
  auto pair = OpenPair();
  ASSERT_EQ(pair.size(), 2u);

  EXPECT_EQ(UdpBusConfig{}.address, "127.0.0.1");
  EXPECT_EQ(pair[1]->local_port(), pair[0]->local_port() + 1);
  // What the sockets are really bound to, not just what the config says.
  EXPECT_EQ(pair[0]->local_address(), "127.0.0.1");
  EXPECT_EQ(pair[1]->local_address(), "127.0.0.1");
}

TEST(UdpBusTest, PortInUseIsAnErrorNamingThePort) {
  auto pair = OpenPair();
  ASSERT_EQ(pair.size(), 2u);
  const std::uint16_t taken = pair[0]->local_port();

  const Result<std::unique_ptr<UdpBus>> second =
      UdpBus::Open({.base_port = taken, .node_count = 2, .node_index = 0});

  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().message.find(std::to_string(taken)), std::string::npos);
}

TEST(UdpBusTest, BadConfigsAreRefused) {
  EXPECT_FALSE(UdpBus::Open({.base_port = 0}).ok());
  EXPECT_FALSE(UdpBus::Open({.base_port = 30'000, .node_count = 2, .node_index = 2}).ok());
  EXPECT_FALSE(UdpBus::Open({.base_port = 65'535, .node_count = 2}).ok());
  EXPECT_FALSE(UdpBus::Open({.address = "not-an-address", .base_port = 30'000}).ok());
}

TEST(UdpBusTest, SendToAPortNobodyHoldsStillSucceeds) {
  auto group = OpenUdpBusGroup(3);
  ASSERT_TRUE(group.ok()) << group.error().message;
  std::vector<std::unique_ptr<UdpBus>> endpoints = std::move(group).value();
  endpoints.pop_back();  // its port goes quiet, as when a DUT process has not started yet

  const Result<void> sent = endpoints[0]->Send(Sample(), 0);

  EXPECT_TRUE(sent.ok());
  EXPECT_EQ(ReceiveFrames(*endpoints[1], 1).size(), 1u);
}

}  // namespace
}  // namespace hilrig::rig
