// The bus that hands the DUT the frames the step requests carried: filters and the error-frame
// mask as on the UDP bus, frames delivered once, sends counted and dropped.
#include "dut_emu/link_can_bus.h"

#include <gtest/gtest.h>

#include <array>

#include "rig/can_bus.h"
#include "rig/can_frame.h"

namespace hilrig::dut_emu {
namespace {

const std::array<std::uint8_t, 1> kPayload = {1};

TEST(LinkCanBusTest, HandsOverDeliveredFramesOnceStampedWithTheReceiveTime) {
  LinkCanBus bus;
  const std::array<rig::CanFrame, 2> frames = {rig::CanFrame::Classic(0x10, kPayload),
                                               rig::CanFrame::Classic(0x20, kPayload)};
  bus.Deliver(frames);
  std::vector<rig::TimedCanFrame> out;
  EXPECT_EQ(bus.Receive(7, out), 2u);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].frame.id, 0x20u);
  EXPECT_EQ(out[0].time_ns, 7);
  EXPECT_EQ(bus.Receive(8, out), 0u);
  EXPECT_EQ(bus.counters().frames_received, 2u);
}

TEST(LinkCanBusTest, AppliesTheFiltersAndTheErrorMask) {
  LinkCanBus bus;
  const std::array<rig::CanFilter, 1> only_0x10 = {rig::CanFilter{0x10, 0x7FF}};
  bus.SetFilters(only_0x10);
  const std::array<rig::CanFrame, 3> frames = {
      rig::CanFrame::Classic(0x10, kPayload), rig::CanFrame::Classic(0x20, kPayload),
      rig::CanFrame::ErrorFrame(rig::can_error::kNoAck, {})};
  bus.Deliver(frames);
  std::vector<rig::TimedCanFrame> out;
  EXPECT_EQ(bus.Receive(0, out), 1u);
  bus.SetReceiveErrorFrames(true);
  bus.Deliver(frames);
  EXPECT_EQ(bus.Receive(0, out), 2u);
}

TEST(LinkCanBusTest, CountsSendsAndRefusesInvalidFrames) {
  LinkCanBus bus;
  EXPECT_TRUE(bus.Send(rig::CanFrame::Classic(0x10, kPayload), 0).ok());
  rig::CanFrame invalid = rig::CanFrame::Classic(0x10, kPayload);
  invalid.length = 99;
  EXPECT_FALSE(bus.Send(invalid, 0).ok());
  EXPECT_EQ(bus.counters().frames_sent, 1u);
  EXPECT_EQ(bus.counters().send_failures, 1u);
  std::vector<rig::TimedCanFrame> out;
  EXPECT_EQ(bus.Receive(0, out), 0u);  // a send is no echo
}

}  // namespace
}  // namespace hilrig::dut_emu
