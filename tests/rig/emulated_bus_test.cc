#include "rig/emulated_bus.h"

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <vector>

namespace hilrig::rig {
namespace {

// A standard 8-byte frame occupies 135 bits worst case: 135 us at the default 1 Mbit/s.
constexpr std::int64_t kEightByteFrameNs = 135'000;
constexpr std::int64_t kFarFutureNs = 1'000'000'000;

CanFrame Frame(std::uint32_t id) {
  return CanFrame::Classic(id, std::array<std::uint8_t, 8>{1, 2, 3, 4, 5, 6, 7, 8});
}

std::vector<TimedCanFrame> ReceiveAll(CanBus& endpoint, std::int64_t now_ns = kFarFutureNs) {
  std::vector<TimedCanFrame> out;
  endpoint.Receive(now_ns, out);
  return out;
}

std::vector<std::uint32_t> Ids(const std::vector<TimedCanFrame>& frames) {
  std::vector<std::uint32_t> ids;
  for (const TimedCanFrame& timed : frames) ids.push_back(timed.frame.id);
  return ids;
}

TEST(EmulatedBusTest, DeliversToOtherEndpointsButNotSender) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto a = bus.Connect("a");
  auto b = bus.Connect("b");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*a)), std::vector<std::uint32_t>{0x101});
  EXPECT_EQ(Ids(ReceiveAll(*b)), std::vector<std::uint32_t>{0x101});
  EXPECT_TRUE(ReceiveAll(*sender).empty());
}

TEST(EmulatedBusTest, ReceiveOwnFramesEchoesToSender) {
  EmulatedBus bus({.receive_own_frames = true});
  auto sender = bus.Connect("sender");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*sender)), std::vector<std::uint32_t>{0x101});
}

TEST(EmulatedBusTest, DeliveredFrameIsIntact) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame, Frame(0x101));
}

TEST(EmulatedBusTest, FrameArrivesWhenSerializationFinishes) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  ASSERT_TRUE(sender->Send(Frame(0x101), 1'000).ok());
  const std::int64_t finish_ns = 1'000 + kEightByteFrameNs;

  const std::vector<TimedCanFrame> early = ReceiveAll(*receiver, finish_ns - 1);
  const std::vector<TimedCanFrame> on_time = ReceiveAll(*receiver, finish_ns);

  EXPECT_TRUE(early.empty());
  ASSERT_EQ(on_time.size(), 1u);
  EXPECT_EQ(on_time[0].time_ns, finish_ns);
}

TEST(EmulatedBusTest, BackToBackFramesSerialize) {
  EmulatedBus bus;
  auto a = bus.Connect("a");
  auto b = bus.Connect("b");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(a->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(b->Send(Frame(0x102), 0).ok());  // bus still busy with a's frame
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[0].time_ns, kEightByteFrameNs);
  EXPECT_EQ(received[1].time_ns, 2 * kEightByteFrameNs);
}

TEST(EmulatedBusTest, FrameOnIdleBusStartsWhenSent) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 1'000'000).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[1].time_ns, 1'000'000 + kEightByteFrameNs);
}

TEST(EmulatedBusTest, ReceiveAppendsAndReturnsCount) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());
  std::vector<TimedCanFrame> out(1);

  const std::size_t appended = receiver->Receive(kFarFutureNs, out);

  EXPECT_EQ(appended, 2u);
  EXPECT_EQ(out.size(), 3u);
}

TEST(EmulatedBusTest, FiltersSelectFrames) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x102, .mask = 0x7FF}};
  receiver->SetFilters(filters);

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*receiver)), std::vector<std::uint32_t>{0x102});
}

TEST(EmulatedBusTest, InvertedFilterDropsOneId) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x101, .mask = 0x7FF, .inverted = true}};
  receiver->SetFilters(filters);

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*receiver)), std::vector<std::uint32_t>{0x102});
}

TEST(EmulatedBusTest, ExtendedFilterIgnoresStandardFrameWithSameId) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x101, .mask = 0x1FFFFFFF, .extended = true}};
  receiver->SetFilters(filters);

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(CanFrame::ClassicExtended(0x101, {}), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_TRUE(received[0].frame.extended);
}

TEST(EmulatedBusTest, ErrorFramesOnlyReachEndpointsThatAskForThem) {
  EmulatedBus bus;
  auto injector = bus.Connect("injector");
  auto plain = bus.Connect("plain");
  auto monitor = bus.Connect("monitor");
  monitor->SetReceiveErrorFrames(true);

  ASSERT_TRUE(injector->Send(CanFrame::ErrorFrame(0x4, {}), 0).ok());

  EXPECT_TRUE(ReceiveAll(*plain).empty());
  EXPECT_EQ(ReceiveAll(*monitor).size(), 1u);
}

TEST(EmulatedBusTest, InvalidFrameIsRefusedAndCounted) {
  EmulatedBus bus;
  auto sender = bus.Connect("dut");
  auto receiver = bus.Connect("receiver");
  CanFrame invalid = Frame(0x101);
  invalid.id = 0x800;

  const Result<void> result = sender->Send(invalid, 0);

  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("dut"), std::string::npos);
  EXPECT_EQ(sender->counters().send_failures, 1u);
  EXPECT_EQ(sender->counters().frames_sent, 0u);
  EXPECT_TRUE(ReceiveAll(*receiver).empty());
}

TEST(EmulatedBusTest, CountsSentAndReceivedFrames) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());
  ReceiveAll(*receiver);

  EXPECT_EQ(sender->counters().frames_sent, 2u);
  EXPECT_EQ(receiver->counters().frames_received, 2u);
}

TEST(EmulatedBusTest, FullRxQueueDropsAndCounts) {
  EmulatedBus bus({.rx_queue_capacity = 2});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");

  for (std::uint32_t id = 0x101; id <= 0x103; ++id) ASSERT_TRUE(sender->Send(Frame(id), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*receiver)), (std::vector<std::uint32_t>{0x101, 0x102}));
  EXPECT_EQ(receiver->counters().frames_dropped_rx_overflow, 1u);
}

TEST(EmulatedBusTest, EndpointDestroyedWithPendingTrafficDetachesCleanly) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto leaver = bus.Connect("leaver");
  auto stayer = bus.Connect("stayer");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());  // still queued, undelivered, for leaver

  leaver.reset();
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*stayer)), (std::vector<std::uint32_t>{0x101, 0x102}));
}

TEST(EmulatedBusTest, StatsSumFrameDurations) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 10'000'000).ok());

  EXPECT_EQ(bus.stats().frames, 2u);
  EXPECT_EQ(bus.stats().busy_ns, 2 * kEightByteFrameNs);
}

TEST(EmulatedBusTest, EndpointsSurviveMovingTheBus) {
  EmulatedBus original;
  EmulatedBus moved;
  auto sender = original.Connect("sender");

  moved = std::move(original);
  auto receiver = moved.Connect("receiver");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());

  EXPECT_EQ(ReceiveAll(*receiver).size(), 1u);
}

TEST(EmulatedBusDeathTest, DestroyingBusBeforeEndpointsAborts) {
  EXPECT_DEATH(
      {
        auto bus = std::make_unique<EmulatedBus>();
        auto endpoint = bus->Connect("dut");
        bus.reset();
      },
      "still connected: dut");
}

}  // namespace
}  // namespace hilrig::rig
