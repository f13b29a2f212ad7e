// StagedCanBus over an emulated bus: the "runner" endpoint sends, the staged "dut" endpoint
// receives. Frames are told apart by their first payload byte.
#include "dut_emu/staged_can_bus.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "rig/emulated_bus.h"

namespace hilrig::dut_emu {
namespace {

// Late enough for any frame sent at 0 to have finished on the wire.
constexpr std::int64_t kAfterTheWireNs = 10'000'000;

class StagedCanBusTest : public ::testing::Test {
 protected:
  explicit StagedCanBusTest(UnannouncedFrames unannounced = UnannouncedFrames::kEarly)
      : runner_(medium_.Connect("runner")), staged_(medium_.Connect("dut"), unannounced) {}

  void SendFrame(std::uint8_t marker) {
    const std::array<std::uint8_t, 1> payload = {marker};
    ASSERT_TRUE(runner_->Send(rig::CanFrame::Classic(0x101, payload), 0).ok());
  }

  // The frames the DUT gets at a step, as (marker, time) pairs.
  std::vector<std::pair<int, std::int64_t>> Take(std::int64_t now_ns = kAfterTheWireNs) {
    std::vector<rig::TimedCanFrame> frames;
    staged_.Receive(now_ns, frames);
    std::vector<std::pair<int, std::int64_t>> taken;
    for (const rig::TimedCanFrame& timed : frames) {
      taken.emplace_back(timed.frame.data[0], timed.time_ns);
    }
    return taken;
  }

  rig::EmulatedBus medium_;
  std::unique_ptr<rig::CanBus> runner_;
  StagedCanBus staged_;
};

using Taken = std::vector<std::pair<int, std::int64_t>>;

TEST_F(StagedCanBusTest, AnnouncedFramesCarryTheRunnersTimes) {
  SendFrame(1);
  SendFrame(2);
  const std::array<std::int64_t, 2> times_ns = {500, 700};
  staged_.Announce(times_ns);
  staged_.Pump(kAfterTheWireNs);
  EXPECT_EQ(staged_.missing(), 0u);
  EXPECT_EQ(staged_.early(), 0u);
  EXPECT_EQ(Take(), (Taken{{1, 500}, {2, 700}}));
  EXPECT_EQ(staged_.handed_over(), 2u);
}

TEST_F(StagedCanBusTest, FramesAheadOfTheirAnnouncementWaitForIt) {
  SendFrame(1);
  SendFrame(2);
  SendFrame(3);
  const std::array<std::int64_t, 1> first_ns = {500};
  staged_.Announce(first_ns);
  staged_.Pump(kAfterTheWireNs);
  EXPECT_EQ(staged_.early(), 2u);
  EXPECT_EQ(Take(), (Taken{{1, 500}}));
  EXPECT_EQ(Take(), Taken{}) << "a step that announces nothing gets nothing";
  const std::array<std::int64_t, 2> next_ns = {1'500, 1'600};
  staged_.Announce(next_ns);
  EXPECT_EQ(staged_.early(), 0u);
  EXPECT_EQ(Take(), (Taken{{2, 1'500}, {3, 1'600}}));
  EXPECT_EQ(staged_.handed_over(), 3u);
}

TEST_F(StagedCanBusTest, LateFrameReachesTheNextStepWithItsAnnouncedTime) {
  const std::array<std::int64_t, 1> times_ns = {500};
  staged_.Announce(times_ns);
  EXPECT_EQ(Take(), Taken{});
  EXPECT_EQ(staged_.missing(), 1u);
  SendFrame(7);  // the bus acts at the latest time it saw, so it is on the wire until later
  EXPECT_EQ(Take(2 * kAfterTheWireNs), (Taken{{7, 500}}));
  EXPECT_EQ(staged_.missing(), 0u);
}

class PassThroughStagedCanBusTest : public StagedCanBusTest {
 protected:
  PassThroughStagedCanBusTest() : StagedCanBusTest(UnannouncedFrames::kPassThrough) {}
};

TEST_F(PassThroughStagedCanBusTest, UnannouncedFramesKeepTheBusStamp) {
  SendFrame(4);
  const Taken taken = Take();
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].first, 4);
  EXPECT_GT(taken[0].second, 0) << "stamped by the bus when the frame finished";
  EXPECT_LE(taken[0].second, kAfterTheWireNs);
  EXPECT_EQ(staged_.early(), 0u);
}

// hilrig run --can announces the frames it puts on a real bus; a DUT a step behind has taken them
// already when the announcement comes, so it must not wait for them again.
TEST_F(PassThroughStagedCanBusTest, AnnouncementsNeitherWaitNorRestamp) {
  SendFrame(4);
  const Taken taken_early = Take();
  ASSERT_EQ(taken_early.size(), 1u);
  const std::array<std::int64_t, 1> times_ns = {500};
  staged_.Announce(times_ns);
  EXPECT_EQ(staged_.missing(), 0u) << "the announced frame was handed over already";
  SendFrame(5);
  const Taken taken_late = Take(2 * kAfterTheWireNs);
  ASSERT_EQ(taken_late.size(), 1u);
  EXPECT_EQ(taken_late[0].first, 5);
  EXPECT_NE(taken_late[0].second, 500) << "keeps the bus stamp";
  EXPECT_EQ(staged_.missing(), 0u);
}

}  // namespace
}  // namespace hilrig::dut_emu
