#include "rig/can_bus.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

namespace hilrig::rig {
namespace {

CanFrame Standard(std::uint32_t id) { return CanFrame::Classic(id, {}); }
CanFrame Extended(std::uint32_t id) { return CanFrame::ClassicExtended(id, {}); }

TEST(FilterAcceptsTest, EmptyListAcceptsEverything) {
  EXPECT_TRUE(FilterAccepts({}, Standard(0x123)));
  EXPECT_TRUE(FilterAccepts({}, Extended(0x1234567)));
}

TEST(FilterAcceptsTest, ExactFilterPassesOnlyItsId) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x123, .mask = 0x7FF}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x123)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x124)));
}

TEST(FilterAcceptsTest, MaskSelectsARange) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x100, .mask = 0x7F0}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x107)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x110)));
}

TEST(FilterAcceptsTest, ExtendedFlagMustMatch) {
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x123, .mask = 0x7FF}};

  EXPECT_FALSE(FilterAccepts(filters, Extended(0x123)));
}

TEST(FilterAcceptsTest, ExtendedFilterMatchesExtendedFrames) {
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x18FF0000, .mask = 0x1FFF0000, .extended = true}};

  EXPECT_TRUE(FilterAccepts(filters, Extended(0x18FF1234)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x123)));
}

TEST(FilterAcceptsTest, InvertedFilterPassesEverythingElse) {
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x123, .mask = 0x7FF, .inverted = true}};

  EXPECT_FALSE(FilterAccepts(filters, Standard(0x123)));
  EXPECT_TRUE(FilterAccepts(filters, Standard(0x124)));
}

TEST(FilterAcceptsTest, AnyMatchingFilterPasses) {
  const std::array<CanFilter, 2> filters = {CanFilter{.id = 0x101, .mask = 0x7FF},
                                            CanFilter{.id = 0x202, .mask = 0x7FF}};

  EXPECT_TRUE(FilterAccepts(filters, Standard(0x202)));
  EXPECT_FALSE(FilterAccepts(filters, Standard(0x303)));
}

// Moved from the gs_usb protocol test: GsUsbBus now applies the shared decoder.
std::optional<BusState> Announced(const CanFrame& frame) {
  return AnnouncedBusState(DecodeErrorFrame(frame, 0));
}

TEST(ErrorFrameDecodeTest, ErrorFramesDecodeIntoStates) {
  EXPECT_EQ(Announced(CanFrame::ErrorFrame(can_error::kBusOff, {})), BusState::kBusOff);
  EXPECT_EQ(Announced(CanFrame::ErrorFrame(can_error::kRestarted, {})), BusState::kErrorActive);
  EXPECT_EQ(Announced(CanFrame::ErrorFrame(can_error::kController, {0, can_error::kCtrlTxWarning})),
            BusState::kErrorWarning);
  const CanFrame passive = CanFrame::ErrorFrame(
      can_error::kController | can_error::kCounters,
      {0, can_error::kCtrlRxPassive | can_error::kCtrlRxOverflow, 0, 0, 0, 0, 90, 128});
  const std::vector<BusEvent> events = DecodeErrorFrame(passive, 0);
  EXPECT_EQ(AnnouncedBusState(events), BusState::kErrorPassive);
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const BusEvent& event) {
    return event.kind == BusEventKind::kRxOverflow;
  }));
  ASSERT_FALSE(events.empty());
  EXPECT_TRUE(events.front().has_counters);
  EXPECT_EQ(events.front().tx_error_count, 90);
  EXPECT_EQ(events.front().rx_error_count, 128);
  EXPECT_FALSE(Announced(CanFrame::ErrorFrame(can_error::kNoAck, {})));
}

TEST(ErrorFrameDecodeTest, MostSevereAnnouncedStateWins) {
  EXPECT_EQ(Announced(CanFrame::ErrorFrame(can_error::kBusOff | can_error::kController,
                                           {0, can_error::kCtrlTxPassive})),
            BusState::kBusOff);
  EXPECT_EQ(Announced(CanFrame::ErrorFrame(
                can_error::kController, {0, can_error::kCtrlRxPassive | can_error::kCtrlTxWarning |
                                                can_error::kCtrlActive})),
            BusState::kErrorPassive);
}

}  // namespace
}  // namespace hilrig::rig
