// OpenCanBus: every scheme's URI parses to its backend's arguments, bad URIs are errors naming the
// URI and the problem, and the emulated, UDP and gs_usb (over the fake device) backends open.
#include "rig/can_open.h"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "tests/rig/fake_gs_usb_device.h"

namespace hilrig::rig {
namespace {

constexpr int kMaxPolls = 100000;

TEST(CanBusUriTest, ParsesEachScheme) {
  auto emulated = ParseCanBusUri("emulated");
  ASSERT_TRUE(emulated.ok());
  EXPECT_EQ(emulated.value().scheme, CanBusUri::Scheme::kEmulated);

  auto udp = ParseCanBusUri("udp:30000");
  ASSERT_TRUE(udp.ok());
  EXPECT_EQ(udp.value().scheme, CanBusUri::Scheme::kUdp);
  EXPECT_EQ(udp.value().udp.base_port, 30000);
  EXPECT_EQ(udp.value().udp.node_index, 1u);
  EXPECT_EQ(udp.value().udp.node_count, 2u);

  auto udp_full = ParseCanBusUri("udp:30000:2:5");
  ASSERT_TRUE(udp_full.ok());
  EXPECT_EQ(udp_full.value().udp.node_index, 2u);
  EXPECT_EQ(udp_full.value().udp.node_count, 5u);

  auto socketcan = ParseCanBusUri("socketcan:vcan0");
  ASSERT_TRUE(socketcan.ok());
  EXPECT_EQ(socketcan.value().scheme, CanBusUri::Scheme::kSocketCan);
  EXPECT_EQ(socketcan.value().interface, "vcan0");

  auto gs_usb = ParseCanBusUri("gs_usb");
  ASSERT_TRUE(gs_usb.ok());
  EXPECT_EQ(gs_usb.value().scheme, CanBusUri::Scheme::kGsUsb);
  EXPECT_EQ(gs_usb.value().usb_serial, "");

  auto gs_usb_serial = ParseCanBusUri("gs_usb:003A00425253");
  ASSERT_TRUE(gs_usb_serial.ok());
  EXPECT_EQ(gs_usb_serial.value().usb_serial, "003A00425253");
}

TEST(CanBusUriTest, BadUrisNameTheUriAndTheProblem) {
  const std::array<std::pair<const char*, const char*>, 12> cases = {{
      {"", "unknown scheme"},
      {"can0", "unknown scheme \"can0\""},
      {"emulated:1", "emulated takes no arguments"},
      {"udp", "expected udp:BASE_PORT"},
      {"udp:", "UDP base port \"\" is not a valid number"},
      {"udp:70000", "UDP base port \"70000\" is not a valid number"},
      {"udp:0", "UDP base port 0"},
      {"udp:30000:2", "node index not below node count"},
      {"udp:30000:1:2:3", "expected udp:BASE_PORT"},
      {"socketcan", "expected socketcan:IFACE"},
      {"socketcan:can0:x", "expected socketcan:IFACE"},
      {"gs_usb:", "expected gs_usb or gs_usb:SERIAL"},
  }};
  for (const auto& [uri, problem] : cases) {
    auto parsed = ParseCanBusUri(uri);
    ASSERT_FALSE(parsed.ok()) << uri;
    EXPECT_NE(parsed.error().message.find("CAN bus \"" + std::string(uri) + "\""),
              std::string::npos)
        << parsed.error().message;
    EXPECT_NE(parsed.error().message.find(problem), std::string::npos) << parsed.error().message;
    auto opened = OpenCanBus(uri);
    ASSERT_FALSE(opened.ok()) << uri;
    EXPECT_EQ(opened.error().message, parsed.error().message);
  }
}

TEST(OpenCanBusTest, EmulatedIsALoneNode) {
  auto bus = OpenCanBus("emulated");
  ASSERT_TRUE(bus.ok()) << bus.error().message;
  ASSERT_TRUE(bus.value()->SetReceiveOwnFrames(true).ok());
  const CanFrame frame = CanFrame::Classic(0x123, std::array<std::uint8_t, 1>{7});
  ASSERT_TRUE(bus.value()->Send(frame, 0).ok());
  std::vector<TimedCanFrame> received;
  bus.value()->Receive(1'000'000, received);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame.id, 0x123u);
  EXPECT_TRUE(received[0].tx_echo);
}

TEST(OpenCanBusTest, UdpJoinsTheBusAtItsNode) {
  auto group = OpenUdpBusGroup(3);
  ASSERT_TRUE(group.ok()) << group.error().message;
  std::vector<std::unique_ptr<UdpBus>> nodes = std::move(group).value();
  const std::uint16_t base_port = nodes[0]->local_port();
  nodes[2].reset();  // frees node 2's port for the URI to bind

  const std::string uri = "udp:" + std::to_string(base_port) + ":2:3";
  auto bus = OpenCanBus(uri);
  ASSERT_TRUE(bus.ok()) << bus.error().message;
  const CanFrame frame = CanFrame::Classic(0x42, std::array<std::uint8_t, 2>{1, 2});
  ASSERT_TRUE(nodes[0]->Send(frame, 0).ok());
  std::vector<TimedCanFrame> received;
  for (int poll = 0; poll < kMaxPolls && received.empty(); ++poll) {
    bus.value()->Receive(0, received);
    std::this_thread::yield();
  }
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame.id, 0x42u);
}

TEST(OpenCanBusTest, GsUsbOpensTheAdapterWithTheSerialAsked) {
  FakeCanWire wire;
  FakeGsUsbDevice* device = nullptr;
  std::string serial_asked;
  auto bus = OpenCanBus("gs_usb:ABC123", [&](const std::string& serial) {
    serial_asked = serial;
    auto owned = std::make_unique<FakeGsUsbDevice>(wire);
    device = owned.get();
    return Result<std::unique_ptr<GsUsbTransport>>(std::move(owned));
  });
  ASSERT_TRUE(bus.ok()) << bus.error().message;
  EXPECT_EQ(serial_asked, "ABC123");
  ASSERT_NE(device, nullptr);
  EXPECT_TRUE(device->started());
}

TEST(OpenCanBusTest, AnAdapterThatCannotOpenIsAnErrorNamingTheUri) {
  auto bus = OpenCanBus("gs_usb", [](const std::string&) {
    return Result<std::unique_ptr<GsUsbTransport>>(MakeError("no gs_usb device found"));
  });
  ASSERT_FALSE(bus.ok());
  EXPECT_EQ(bus.error().message, "CAN bus \"gs_usb\": no gs_usb device found");
}

}  // namespace
}  // namespace hilrig::rig
