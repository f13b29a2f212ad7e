#include "tests/rig/can_bus_conformance.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hilrig::rig {

namespace {

constexpr std::array<std::uint8_t, 4> kMarkerPayload = {0x4D, 0x41, 0x52, 0x4B};  // "MARK"

CanFrame Marker(std::uint32_t id) { return CanFrame::Classic(id, kMarkerPayload); }

CanFrame Numbered(std::uint32_t id, std::uint8_t number) {
  return CanFrame::Classic(id, std::array<std::uint8_t, 2>{number, 0xA5});
}

std::vector<CanFrame> FramesOf(const std::vector<TimedCanFrame>& timed) {
  std::vector<CanFrame> frames;
  for (const TimedCanFrame& t : timed) frames.push_back(t.frame);
  return frames;
}

// Payload bytes that differ per length, so a truncated or shifted payload cannot pass.
std::vector<std::uint8_t> PayloadOfLength(std::size_t length) {
  std::vector<std::uint8_t> payload;
  for (std::size_t i = 0; i < length; ++i)
    payload.push_back(static_cast<std::uint8_t>(length * 7 + i));
  return payload;
}

}  // namespace

TEST_P(CanBusConformanceTest, FrameReachesOtherEndpoint) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const CanFrame frame = Numbered(0x123, 1);

  ASSERT_TRUE(Send(*endpoints[0], frame).ok());
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], 1);

  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].frame, frame);
  EXPECT_FALSE(received[0].tx_echo);
}

TEST_P(CanBusConformanceTest, FrameReachesEveryOtherEndpoint) {
  auto endpoints = MakeEndpoints(3);
  ASSERT_EQ(endpoints.size(), 3u);

  ASSERT_TRUE(Send(*endpoints[1], Numbered(0x321, 2)).ok());

  EXPECT_EQ(FramesOf(ReceiveFrames(*endpoints[0], 1)), std::vector{Numbered(0x321, 2)});
  EXPECT_EQ(FramesOf(ReceiveFrames(*endpoints[2], 1)), std::vector{Numbered(0x321, 2)});
}

TEST_P(CanBusConformanceTest, ClassicPayloadsOfEveryLengthRoundTrip) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  std::vector<CanFrame> sent;
  for (std::size_t length = 0; length <= CanFrame::kMaxClassicPayload; ++length) {
    sent.push_back(CanFrame::Classic(0x200 + length, PayloadOfLength(length)));
  }

  for (const CanFrame& frame : sent) ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], sent.size());

  EXPECT_EQ(FramesOf(received), sent);
}

TEST_P(CanBusConformanceTest, FdPayloadsOfEveryLengthRoundTrip) {
  if (!backend_->SupportsFd()) GTEST_SKIP() << backend_->Name() << " has no CAN FD";
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  std::vector<CanFrame> sent;
  for (std::size_t length = 0; length <= CanFrame::kMaxFdPayload; ++length) {
    if (!IsValidFdLength(length)) continue;
    const bool brs = length % 2 == 0;
    sent.push_back(CanFrame::Fd(0x300 + length, PayloadOfLength(length), brs));
  }
  sent.push_back(CanFrame::FdExtended(0x1ABCDE00, PayloadOfLength(64), true));

  for (const CanFrame& frame : sent) ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], sent.size());

  EXPECT_EQ(FramesOf(received), sent);
}

TEST_P(CanBusConformanceTest, ExtendedAndRemoteFramesRoundTrip) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::vector<CanFrame> sent = {
      CanFrame::ClassicExtended(0x1FFFFFFF, PayloadOfLength(8)),
      CanFrame::Remote(0x456, 4, /*extended=*/false),
      CanFrame::Remote(0x12345678, 8, /*extended=*/true),
  };

  for (const CanFrame& frame : sent) ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], sent.size());

  EXPECT_EQ(FramesOf(received), sent);
}

TEST_P(CanBusConformanceTest, OneSendersOrderIsKeptWhateverTheIds) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  std::vector<CanFrame> sent;
  for (std::uint8_t k = 0; k < 8; ++k) sent.push_back(Numbered(0x700 - 0x10 * k, k));

  for (const CanFrame& frame : sent) ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], sent.size());

  EXPECT_EQ(FramesOf(received), sent);
}

TEST_P(CanBusConformanceTest, TimestampsNeverDecrease) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);

  for (std::uint8_t k = 0; k < 6; ++k) {
    ASSERT_TRUE(Send(*endpoints[0], Numbered(0x140, k)).ok());
    backend_->Advance(kPollStepNs);
  }
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], 6);

  ASSERT_EQ(received.size(), 6u);
  for (std::size_t i = 1; i < received.size(); ++i) {
    EXPECT_LE(received[i - 1].time_ns, received[i].time_ns) << "frame " << i;
  }
}

TEST_P(CanBusConformanceTest, IdMaskFilterSelectsFrames) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::array<CanFilter, 1> filters = {CanFilter{.id = 0x120, .mask = 0x7F0}};
  endpoints[1]->SetFilters(filters);

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x123, 1)).ok());
  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x223, 2)).ok());
  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x12F, 3)).ok());
  SendMarker(*endpoints[0], Marker(0x121));

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], Marker(0x121))),
            (std::vector{Numbered(0x123, 1), Numbered(0x12F, 3)}));
}

TEST_P(CanBusConformanceTest, InvertedFilterPassesAllButItsIds) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x200, .mask = 0x7FF, .inverted = true}};
  endpoints[1]->SetFilters(filters);

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x200, 1)).ok());
  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x201, 2)).ok());
  SendMarker(*endpoints[0], Marker(0x7FF));

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], Marker(0x7FF))), std::vector{Numbered(0x201, 2)});
}

TEST_P(CanBusConformanceTest, FilterWithEffBitSelectsFrameFormat) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::array<CanFilter, 2> filters = {
      CanFilter{.id = 0x123, .mask = 0x7FF},  // standard only: EFF is in the mask by default
      CanFilter{.id = 0x18FF0000, .mask = 0x1FFF0000, .extended = true}};
  endpoints[1]->SetFilters(filters);
  const CanFrame standard = Numbered(0x123, 1);
  const CanFrame extended_same_id = CanFrame::ClassicExtended(0x123, PayloadOfLength(2));
  const CanFrame extended_in_range = CanFrame::ClassicExtended(0x18FF1234, PayloadOfLength(3));
  const CanFrame extended_out_of_range = CanFrame::ClassicExtended(0x18FE1234, PayloadOfLength(4));

  for (const CanFrame& frame :
       {standard, extended_same_id, extended_in_range, extended_out_of_range}) {
    ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  }
  SendMarker(*endpoints[0], Marker(0x123));

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], Marker(0x123))),
            (std::vector{standard, extended_in_range}));
}

TEST_P(CanBusConformanceTest, FilterWithoutEffBitMatchesBothFormats) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x123, .mask = 0x7FF, .match_extended = false}};
  endpoints[1]->SetFilters(filters);
  const CanFrame standard = Numbered(0x123, 1);
  const CanFrame extended = CanFrame::ClassicExtended(0x123, PayloadOfLength(2));
  const CanFrame other = Numbered(0x124, 3);

  for (const CanFrame& frame : {standard, extended, other}) {
    ASSERT_TRUE(Send(*endpoints[0], frame).ok()) << frame;
  }
  SendMarker(*endpoints[0], Marker(0x123));

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], Marker(0x123))),
            (std::vector{standard, extended}));
}

TEST_P(CanBusConformanceTest, FilterWithRtrBitSelectsRemoteFrames) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const std::array<CanFilter, 1> filters = {
      CanFilter{.id = 0x300, .mask = 0x7FF, .remote = true, .match_remote = true}};
  endpoints[1]->SetFilters(filters);
  const CanFrame request = CanFrame::Remote(0x300, 2, /*extended=*/false);
  const CanFrame marker = CanFrame::Remote(0x300, 7, /*extended=*/false);

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x300, 1)).ok());
  ASSERT_TRUE(Send(*endpoints[0], request).ok());
  SendMarker(*endpoints[0], marker);

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], marker)), std::vector{request});
}

TEST_P(CanBusConformanceTest, ErrorFramesReachOnlyEndpointsThatAskForThem) {
  auto endpoints = MakeEndpoints(3);
  ASSERT_EQ(endpoints.size(), 3u);
  endpoints[2]->SetReceiveErrorFrames(true);
  const CanFrame error_frame = CanFrame::ErrorFrame(can_error::kController, {0, 0x08});

  const Result<void> injected = backend_->InjectErrorFrame(*endpoints[0], error_frame);
  if (!injected) GTEST_SKIP() << backend_->Name() << ": " << injected.error().message;
  SendMarker(*endpoints[0], Marker(0x100));

  EXPECT_TRUE(ReceiveUntil(*endpoints[1], Marker(0x100)).empty());
  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[2], Marker(0x100))), std::vector{error_frame});
}

TEST_P(CanBusConformanceTest, ErrorMaskSelectsErrorClasses) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  endpoints[1]->SetErrorFrameMask(can_error::kBusOff);
  const CanFrame controller = CanFrame::ErrorFrame(can_error::kController, {0, 0x08});
  const CanFrame bus_off = CanFrame::ErrorFrame(can_error::kBusOff, {});

  const Result<void> injected = backend_->InjectErrorFrame(*endpoints[0], controller);
  if (!injected) GTEST_SKIP() << backend_->Name() << ": " << injected.error().message;
  backend_->Advance(kPollStepNs);
  ASSERT_TRUE(backend_->InjectErrorFrame(*endpoints[0], bus_off).ok());
  SendMarker(*endpoints[0], Marker(0x100));

  EXPECT_EQ(FramesOf(ReceiveUntil(*endpoints[1], Marker(0x100))), std::vector{bus_off});
}

TEST_P(CanBusConformanceTest, OwnFramesAreNotReceivedByDefault) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x123, 1)).ok());
  SendMarker(*endpoints[1], Marker(0x7FF));

  EXPECT_TRUE(ReceiveUntil(*endpoints[0], Marker(0x7FF)).empty());
}

TEST_P(CanBusConformanceTest, OwnFramesComeBackMarkedWhenEnabled) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  const Result<void> enabled = endpoints[0]->SetReceiveOwnFrames(true);
  ASSERT_TRUE(enabled.ok()) << enabled.error().message;

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x123, 1)).ok());
  const std::vector<TimedCanFrame> echoed = ReceiveFrames(*endpoints[0], 1);
  const std::vector<TimedCanFrame> received = ReceiveFrames(*endpoints[1], 1);

  ASSERT_EQ(echoed.size(), 1u);
  EXPECT_EQ(echoed[0].frame, Numbered(0x123, 1));
  EXPECT_TRUE(echoed[0].tx_echo);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_FALSE(received[0].tx_echo);
}

TEST_P(CanBusConformanceTest, InvalidFrameIsRefusedAndNotSent) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);
  CanFrame invalid = Numbered(0x123, 1);
  invalid.id = 0x800;  // beyond 11 bits for a standard frame

  const Result<void> result = Send(*endpoints[0], invalid);
  SendMarker(*endpoints[0], Marker(0x7FF));

  EXPECT_FALSE(result.ok());
  EXPECT_EQ(endpoints[0]->counters().send_failures, 1u);
  EXPECT_TRUE(ReceiveUntil(*endpoints[1], Marker(0x7FF)).empty());
}

TEST_P(CanBusConformanceTest, CountersCountSentAndReceivedFrames) {
  auto endpoints = MakeEndpoints(2);
  ASSERT_EQ(endpoints.size(), 2u);

  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x101, 1)).ok());
  ASSERT_TRUE(Send(*endpoints[0], Numbered(0x102, 2)).ok());
  ASSERT_EQ(ReceiveFrames(*endpoints[1], 2).size(), 2u);

  EXPECT_EQ(endpoints[0]->counters().frames_sent, 2u);
  EXPECT_EQ(endpoints[1]->counters().frames_received, 2u);
  EXPECT_EQ(endpoints[0]->state(), BusState::kErrorActive);
}

}  // namespace hilrig::rig
