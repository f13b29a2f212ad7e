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
  bus.AdvanceTo(kFarFutureNs);

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

TEST(EmulatedBusTest, EchoIsMarkedAndStampedWhenTheFrameFinishes) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  ASSERT_TRUE(sender->SetReceiveOwnFrames(true).ok());

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  const std::vector<TimedCanFrame> echoed = ReceiveAll(*sender);
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(echoed.size(), 1u);
  EXPECT_TRUE(echoed[0].tx_echo);
  EXPECT_EQ(echoed[0].time_ns, kEightByteFrameNs);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_FALSE(received[0].tx_echo);
}

TEST(EmulatedBusTest, EchoPassesThroughTheSendersFilters) {
  EmulatedBus bus({.receive_own_frames = true});
  auto sender = bus.Connect("sender");
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x102, .mask = 0x7FF}};
  sender->SetFilters(filters);

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  EXPECT_EQ(Ids(ReceiveAll(*sender)), std::vector<std::uint32_t>{0x102});
}

TEST(EmulatedBusTest, SimultaneousFramesGoLowestIdFirst) {
  EmulatedBus bus;
  auto low_priority = bus.Connect("low-priority");
  auto high_priority = bus.Connect("high-priority");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(low_priority->Send(Frame(0x200), 0).ok());
  ASSERT_TRUE(high_priority->Send(Frame(0x100), 0).ok());  // same instant, queued second

  EXPECT_EQ(Ids(ReceiveAll(*receiver)), (std::vector<std::uint32_t>{0x100, 0x200}));
}

TEST(EmulatedBusTest, FramesWaitingForTheBusGoLowestIdFirst) {
  EmulatedBus bus;
  auto a = bus.Connect("a");
  auto b = bus.Connect("b");
  auto c = bus.Connect("c");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(a->Send(Frame(0x300), 0).ok());      // takes the idle bus
  ASSERT_TRUE(b->Send(Frame(0x200), 1'000).ok());  // waits
  ASSERT_TRUE(c->Send(Frame(0x100), 2'000).ok());  // waits, but wins when the bus frees
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  EXPECT_EQ(Ids(received), (std::vector<std::uint32_t>{0x300, 0x100, 0x200}));
  EXPECT_EQ(received[2].time_ns, 3 * kEightByteFrameNs);
}

TEST(EmulatedBusTest, StandardFrameBeatsExtendedWithSameBaseIdAndDataBeatsRemote) {
  EmulatedBus bus;
  auto extended = bus.Connect("extended");
  auto remote = bus.Connect("remote");
  auto standard = bus.Connect("standard");
  auto receiver = bus.Connect("receiver");
  const CanFrame extended_frame = CanFrame::ClassicExtended(0x123u << 18, {});
  const CanFrame remote_frame = CanFrame::Remote(0x123, 8, /*extended=*/false);

  ASSERT_TRUE(extended->Send(extended_frame, 0).ok());
  ASSERT_TRUE(remote->Send(remote_frame, 0).ok());
  ASSERT_TRUE(standard->Send(Frame(0x123), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 3u);
  EXPECT_EQ(received[0].frame, Frame(0x123));
  EXPECT_EQ(received[1].frame, remote_frame);
  EXPECT_EQ(received[2].frame, extended_frame);
}

TEST(EmulatedBusTest, StatsReportQueueingLatencyPerId) {
  EmulatedBus bus;
  auto a = bus.Connect("a");
  auto b = bus.Connect("b");
  auto c = bus.Connect("c");
  ASSERT_TRUE(a->Send(Frame(0x300), 0).ok());
  ASSERT_TRUE(b->Send(Frame(0x200), 1'000).ok());
  ASSERT_TRUE(c->Send(Frame(0x100), 2'000).ok());

  bus.AdvanceTo(kFarFutureNs);
  const EmulatedBusStats stats = bus.stats();

  ASSERT_NE(stats.QueueingFor(0x100), nullptr);
  ASSERT_NE(stats.QueueingFor(0x200), nullptr);
  ASSERT_NE(stats.QueueingFor(0x300), nullptr);
  EXPECT_EQ(stats.QueueingFor(0x300)->max_queueing_ns, 0);
  EXPECT_EQ(stats.QueueingFor(0x100)->max_queueing_ns, kEightByteFrameNs - 2'000);
  EXPECT_EQ(stats.QueueingFor(0x200)->max_queueing_ns, 2 * kEightByteFrameNs - 1'000);
  EXPECT_EQ(stats.QueueingFor(0x100, /*extended=*/true), nullptr);
}

// Ids first seen out of order, extended among them, must each keep their own counts.
TEST(EmulatedBusTest, QueueingStatsStayPerIdWhenIdsArriveOutOfOrder) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  const CanFrame extended = CanFrame::ClassicExtended(0x100, std::array<std::uint8_t, 1>{1});
  ASSERT_TRUE(sender->Send(Frame(0x300), 0).ok());
  ASSERT_TRUE(sender->Send(extended, 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x100), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x200), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x300), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x100), 0).ok());

  bus.AdvanceTo(kFarFutureNs);
  const EmulatedBusStats stats = bus.stats();

  ASSERT_EQ(stats.queueing_by_id.size(), 4u);
  EXPECT_EQ(stats.queueing_by_id[0].id, 0x100u);
  EXPECT_EQ(stats.queueing_by_id[1].id, 0x200u);
  EXPECT_EQ(stats.queueing_by_id[2].id, 0x300u);
  EXPECT_TRUE(stats.queueing_by_id[3].extended);
  EXPECT_EQ(stats.QueueingFor(0x100)->frames, 2u);
  EXPECT_EQ(stats.QueueingFor(0x200)->frames, 1u);
  EXPECT_EQ(stats.QueueingFor(0x300)->frames, 2u);
  EXPECT_EQ(stats.QueueingFor(0x100, /*extended=*/true)->frames, 1u);
}

TEST(EmulatedBusTest, MeanQueueingLatencyAveragesFrames) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());  // waits one frame behind the first

  bus.AdvanceTo(kFarFutureNs);
  const EmulatedBusStats bus_stats = bus.stats();
  const IdQueueingStats* stats = bus_stats.QueueingFor(0x101);

  ASSERT_NE(stats, nullptr);
  EXPECT_EQ(stats->frames, 2u);
  EXPECT_EQ(stats->mean_queueing_ns(), kEightByteFrameNs / 2);
}

TEST(EmulatedBusTest, FrameQueuedAtTheLatestTimeIsDecidedOnlyWhenTimeMovesOn) {
  EmulatedBus bus;
  auto a = bus.Connect("a");
  auto b = bus.Connect("b");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(a->Send(Frame(0x200), 500).ok());
  EXPECT_TRUE(ReceiveAll(*receiver, 500).empty());  // time 500 seen, 0x200 not yet started
  ASSERT_TRUE(b->Send(Frame(0x100), 500).ok());     // still in time to win

  EXPECT_EQ(Ids(ReceiveAll(*receiver)), (std::vector<std::uint32_t>{0x100, 0x200}));
}

TEST(EmulatedBusTest, SendStampedInThePastActsAtTheLatestTime) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  EXPECT_TRUE(ReceiveAll(*receiver, 1'000'000).empty());

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].time_ns, 1'000'000 + kEightByteFrameNs);
}

TEST(EmulatedBusTest, FullTxQueueRefusesWithAClearError) {
  EmulatedBus bus({.tx_queue_capacity = 2});
  auto sender = bus.Connect("dut");
  auto receiver = bus.Connect("receiver");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  const Result<void> refused = sender->Send(Frame(0x103), 0);

  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("dut: TX queue full"), std::string::npos);
  EXPECT_EQ(sender->counters().send_failures, 1u);
  EXPECT_EQ(Ids(ReceiveAll(*receiver)), (std::vector<std::uint32_t>{0x101, 0x102}));
}

TEST(EmulatedBusTest, TxQueueFreesAsFramesStartOnTheWire) {
  EmulatedBus bus({.tx_queue_capacity = 2});
  auto sender = bus.Connect("sender");
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  // By time 1 the first frame is on the wire, so it no longer takes a queue slot.
  const Result<void> sent = sender->Send(Frame(0x103), 1);

  EXPECT_TRUE(sent.ok());
}

TEST(EmulatedBusTest, ErrorMaskSelectsErrorClasses) {
  EmulatedBus bus;
  auto monitor = bus.Connect("monitor");
  monitor->SetErrorFrameMask(can_error::kBusOff | can_error::kRestarted);

  ASSERT_TRUE(bus.InjectErrorFrame(CanFrame::ErrorFrame(can_error::kController, {}), 0).ok());
  ASSERT_TRUE(bus.InjectErrorFrame(CanFrame::ErrorFrame(can_error::kRestarted, {}), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*monitor);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame.id, can_error::kRestarted);
}

TEST(EmulatedBusTest, InjectedErrorFrameTakesTheWireBeforeWaitingFrames) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  receiver->SetReceiveErrorFrames(true);
  const std::int64_t error_frame_ns = 23'000;  // flag 12 + delimiter 8 + intermission 3 bits

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(bus.InjectErrorFrame(CanFrame::ErrorFrame(can_error::kProtocol, {}), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);

  ASSERT_EQ(received.size(), 2u);
  EXPECT_TRUE(received[0].frame.error);
  EXPECT_EQ(received[0].time_ns, error_frame_ns);
  EXPECT_EQ(received[1].time_ns, error_frame_ns + kEightByteFrameNs);
}

TEST(EmulatedBusTest, InjectErrorFrameRefusesADataFrame) {
  EmulatedBus bus;

  EXPECT_FALSE(bus.InjectErrorFrame(Frame(0x101), 0).ok());
}

TEST(EmulatedBusTest, DroppedFramesReachNoReceiverButStillTakeTheWire) {
  EmulatedBus bus({.receive_own_frames = true, .faults = {.seed = 7, .drop_probability = 1.0}});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());

  EXPECT_TRUE(ReceiveAll(*receiver).empty());
  EXPECT_EQ(ReceiveAll(*sender).size(), 1u);  // the sender saw it go out
  EXPECT_EQ(bus.stats().frames_dropped, 1u);
  EXPECT_EQ(bus.stats().busy_ns, kEightByteFrameNs);
}

// Sends `count` frames from one node at 1 kHz and returns the ids the receiver got.
std::vector<std::uint32_t> RunLossyTraffic(const BusFaultConfig& faults, int count) {
  EmulatedBus bus({.faults = faults});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  for (int k = 0; k < count; ++k) {
    EXPECT_TRUE(sender->Send(Frame(0x100 + k % 0x100), k * 1'000'000).ok());
  }
  return Ids(ReceiveAll(*receiver, std::int64_t{count} * 1'000'000 + 1'000'000));
}

TEST(EmulatedBusTest, DropsFollowTheSeedExactly) {
  const BusFaultConfig faults{.seed = 42, .drop_probability = 0.3};

  const std::vector<std::uint32_t> first = RunLossyTraffic(faults, 1000);
  const std::vector<std::uint32_t> again = RunLossyTraffic(faults, 1000);
  const std::vector<std::uint32_t> other_seed =
      RunLossyTraffic({.seed = 43, .drop_probability = 0.3}, 1000);

  EXPECT_EQ(first, again);
  EXPECT_NE(first, other_seed);
  // 1000 draws at p = 0.3: 700 expected delivered, +-45 is over 3 standard deviations.
  EXPECT_NEAR(static_cast<double>(first.size()), 700.0, 45.0);
}

TEST(EmulatedBusTest, CorruptedFramesAreRetransmittedAndArriveIntactInOrder) {
  EmulatedBus bus({.faults = {.seed = 3, .corrupt_probability = 0.4}});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  std::vector<std::uint32_t> sent;
  for (std::uint32_t k = 0; k < 20; ++k) {
    sent.push_back(0x100 + k);
    ASSERT_TRUE(sender->Send(Frame(0x100 + k), k * 1'000'000).ok());
  }

  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver);
  const EmulatedBusStats stats = bus.stats();

  EXPECT_EQ(Ids(received), sent);
  for (const TimedCanFrame& timed : received) EXPECT_EQ(timed.frame, Frame(timed.frame.id));
  EXPECT_GT(stats.frames_corrupted, 0u);
  EXPECT_EQ(stats.frames, sent.size() + stats.frames_corrupted);
}

TEST(EmulatedBusTest, CorruptionReachesReceiversAsACrcProtocolError) {
  EmulatedBus bus({.faults = {.seed = 1, .corrupt_probability = 1.0}});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  receiver->SetReceiveErrorFrames(true);

  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*receiver, kEightByteFrameNs + 23'000);

  ASSERT_EQ(received.size(), 1u);
  const CanFrame& error = received[0].frame;
  EXPECT_TRUE(error.error);
  EXPECT_NE(error.id & can_error::kProtocol, 0u);
  EXPECT_EQ(error.data[3], can_error::kProtLocCrcSequence);
  EXPECT_EQ(error.data[7], 1u);  // the receiver's REC
  EXPECT_EQ(receiver->counters().receive_error_count, 1u);
}

TEST(EmulatedBusTest, PersistentCorruptionTakesTheSenderPassiveThenBusOff) {
  EmulatedBus bus({.faults = {.seed = 1, .corrupt_probability = 1.0}});
  auto sender = bus.Connect("sender");
  auto receiver = bus.Connect("receiver");
  sender->SetErrorFrameMask(can_error::kController | can_error::kBusOff);
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 0).ok());

  const std::vector<TimedCanFrame> events = ReceiveAll(*sender);
  const Result<void> after = sender->Send(Frame(0x103), kFarFutureNs);

  // TEC 96 (12 errors), 128 (16) and 256 (32): warning, passive, bus-off.
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].frame.data[1], can_error::kCtrlTxWarning);
  EXPECT_EQ(events[1].frame.data[1], can_error::kCtrlTxPassive);
  EXPECT_NE(events[2].frame.id & can_error::kBusOff, 0u);
  EXPECT_EQ(sender->state(), BusState::kBusOff);
  EXPECT_EQ(sender->counters().frames_dropped_tx, 2u);
  ASSERT_FALSE(after.ok());
  EXPECT_NE(after.error().message.find("bus-off"), std::string::npos);
  EXPECT_TRUE(ReceiveAll(*receiver).empty());
}

TEST(EmulatedBusTest, BusOffEndpointHearsNothingUntilRestarted) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto dut = bus.Connect("dut");
  dut->SetReceiveErrorFrames(true);
  ASSERT_TRUE(bus.ForceBusOff("dut", 0).ok());

  ASSERT_TRUE(sender->Send(Frame(0x101), 1'000).ok());
  const std::vector<TimedCanFrame> while_off = ReceiveAll(*dut, 1'000'000);
  ASSERT_TRUE(bus.RestartEndpoint("dut", 1'000'000).ok());
  ASSERT_TRUE(sender->Send(Frame(0x102), 1'000'000).ok());
  const std::vector<TimedCanFrame> after_restart = ReceiveAll(*dut);

  ASSERT_EQ(while_off.size(), 1u);
  EXPECT_NE(while_off[0].frame.id & can_error::kBusOff, 0u);
  ASSERT_EQ(after_restart.size(), 2u);
  EXPECT_NE(after_restart[0].frame.id & can_error::kRestarted, 0u);
  EXPECT_EQ(after_restart[1].frame.id, 0x102u);
  EXPECT_EQ(dut->state(), BusState::kErrorActive);
}

TEST(EmulatedBusTest, BusOffForcedMidFrameIsReportedAfterThatFrame) {
  EmulatedBus bus;
  auto sender = bus.Connect("sender");
  auto dut = bus.Connect("dut");
  dut->SetReceiveErrorFrames(true);
  ASSERT_TRUE(sender->Send(Frame(0x101), 0).ok());
  EXPECT_TRUE(ReceiveAll(*dut, 1'000).empty());  // the frame is on the wire, ending later

  ASSERT_TRUE(bus.ForceBusOff("dut", 1'000).ok());
  const std::vector<TimedCanFrame> received = ReceiveAll(*dut);

  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[0].frame, Frame(0x101));
  EXPECT_TRUE(received[1].frame.error);
  EXPECT_EQ(received[1].time_ns, received[0].time_ns);
}

TEST(EmulatedBusTest, BusOffEndpointRestartsByItselfWhenConfigured) {
  EmulatedBus bus({.bus_off_restart_ns = 10'000'000});
  auto dut = bus.Connect("dut");
  dut->SetErrorFrameMask(can_error::kRestarted);
  ASSERT_TRUE(bus.ForceBusOff("dut", 0).ok());

  const std::vector<TimedCanFrame> early = ReceiveAll(*dut, 10'000'000 - 1);
  const std::vector<TimedCanFrame> due = ReceiveAll(*dut, 10'000'000);

  EXPECT_TRUE(early.empty());
  ASSERT_EQ(due.size(), 1u);
  EXPECT_EQ(due[0].time_ns, 10'000'000);
  EXPECT_EQ(dut->state(), BusState::kErrorActive);
}

TEST(EmulatedBusTest, FaultControlsRefuseUnknownEndpoints) {
  EmulatedBus bus;

  const Result<void> result = bus.ForceBusOff("nobody", 0);

  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("nobody"), std::string::npos);
}

// The tactile bus of the rig: seven nodes, ids 0x101..0x107 (node 7 lowest priority), one
// 8-byte frame per sample, all sampling on the same tick.
struct NodeTraffic {
  EmulatedBusStats stats;
  std::int64_t elapsed_ns = 0;
};

NodeTraffic RunSevenNodes(std::int64_t rate_hz, std::int64_t duration_ns) {
  constexpr int kNodes = 7;
  EmulatedBus bus;
  std::vector<std::unique_ptr<CanBus>> nodes;
  for (int k = 0; k < kNodes; ++k) nodes.push_back(bus.Connect("node" + std::to_string(k + 1)));
  const std::int64_t period_ns = 1'000'000'000 / rate_hz;
  for (std::int64_t t = 0; t < duration_ns; t += period_ns) {
    for (int k = 0; k < kNodes; ++k) {
      EXPECT_TRUE(nodes[k]->Send(Frame(0x101 + k), t).ok());
    }
  }
  bus.AdvanceTo(duration_ns + period_ns);
  return {bus.stats(), duration_ns};
}

TEST(EmulatedBusLoadTest, SevenNodesAt50HzLoadUnderFivePercent) {
  const NodeTraffic traffic = RunSevenNodes(50, 1'000'000'000);

  const double load = traffic.stats.LoadOver(traffic.elapsed_ns);

  RecordProperty("load_7_nodes_50_hz", ::testing::PrintToString(load));
  EXPECT_EQ(traffic.stats.frames, 7u * 50u);
  EXPECT_LT(load, 0.05);
}

TEST(EmulatedBusLoadTest, LowestPriorityNodeWaitsForEachHigherNodeAt1kHz) {
  const NodeTraffic traffic = RunSevenNodes(1000, 100'000'000);

  const IdQueueingStats* lowest = traffic.stats.QueueingFor(0x107);
  const IdQueueingStats* highest = traffic.stats.QueueingFor(0x101);

  ASSERT_NE(lowest, nullptr);
  ASSERT_NE(highest, nullptr);
  RecordProperty("max_latency_ns_node_7", ::testing::PrintToString(lowest->max_queueing_ns));
  RecordProperty("load_7_nodes_1_khz",
                 ::testing::PrintToString(traffic.stats.LoadOver(traffic.elapsed_ns)));
  EXPECT_GT(lowest->max_queueing_ns, 0);
  EXPECT_LE(lowest->max_queueing_ns, 6 * kEightByteFrameNs);
  EXPECT_EQ(highest->max_queueing_ns, 0);
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
