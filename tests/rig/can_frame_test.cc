#include "rig/can_frame.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace hilrig::rig {
namespace {

std::vector<std::uint8_t> Bytes(std::size_t count) {
  return std::vector<std::uint8_t>(count, 0xA5);
}

// ---- DLC mapping ----

TEST(DlcTest, FdLengthsMapToTheirDlc) {
  EXPECT_EQ(DlcFromLength(0), 0);
  EXPECT_EQ(DlcFromLength(8), 8);
  EXPECT_EQ(DlcFromLength(12), 9);
  EXPECT_EQ(DlcFromLength(24), 12);
  EXPECT_EQ(DlcFromLength(64), 15);
}

TEST(DlcTest, InBetweenLengthsRoundUpToNextDlc) {
  EXPECT_EQ(DlcFromLength(9), 9);
  EXPECT_EQ(DlcFromLength(13), 10);
  EXPECT_EQ(DlcFromLength(33), 14);
}

TEST(DlcTest, FdDlcMapsBackToLength) {
  EXPECT_EQ(LengthFromDlc(9, /*fd=*/true), 12u);
  EXPECT_EQ(LengthFromDlc(13, /*fd=*/true), 32u);
  EXPECT_EQ(LengthFromDlc(15, /*fd=*/true), 64u);
}

TEST(DlcTest, ClassicDlcAboveEightMeansEightBytes) {
  EXPECT_EQ(LengthFromDlc(5, /*fd=*/false), 5u);
  EXPECT_EQ(LengthFromDlc(9, /*fd=*/false), 8u);
  EXPECT_EQ(LengthFromDlc(15, /*fd=*/false), 8u);
}

TEST(DlcTest, ValidFdLengthsAreExactlyTheDlcTable) {
  std::vector<std::size_t> valid;
  for (std::size_t length = 0; length <= 70; ++length) {
    if (IsValidFdLength(length)) valid.push_back(length);
  }

  EXPECT_EQ(valid,
            (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64}));
}

// ---- factories and equality ----

TEST(CanFrameTest, ClassicCopiesIdAndPayload) {
  const std::array<std::uint8_t, 3> payload = {1, 2, 3};

  const CanFrame frame = CanFrame::Classic(0x123, payload);

  EXPECT_EQ(frame.id, 0x123u);
  EXPECT_FALSE(frame.extended);
  EXPECT_FALSE(frame.fd);
  EXPECT_EQ(std::vector<std::uint8_t>(frame.payload().begin(), frame.payload().end()),
            (std::vector<std::uint8_t>{1, 2, 3}));
}

TEST(CanFrameTest, RemoteFrameHasLengthButNoPayload) {
  const CanFrame frame = CanFrame::Remote(0x42, 4, /*extended=*/false);

  EXPECT_TRUE(frame.remote);
  EXPECT_EQ(frame.length, 4);
  EXPECT_TRUE(frame.payload().empty());
}

TEST(CanFrameTest, EqualityIgnoresBytesBeyondLength) {
  CanFrame a = CanFrame::Classic(0x10, std::array<std::uint8_t, 2>{7, 8});
  CanFrame b = a;
  b.data[5] = 0xFF;

  EXPECT_EQ(a, b);
}

TEST(CanFrameTest, EqualityComparesFlags) {
  const CanFrame classic = CanFrame::Fd(0x10, Bytes(8), /*bitrate_switch=*/false);
  const CanFrame brs = CanFrame::Fd(0x10, Bytes(8), /*bitrate_switch=*/true);

  EXPECT_NE(classic, brs);
}

TEST(CanFrameDeathTest, ClassicRejectsNineBytes) {
  EXPECT_DEATH(CanFrame::Classic(0x10, Bytes(9)), "payload length");
}

TEST(CanFrameDeathTest, ClassicRejectsExtendedSizedId) {
  EXPECT_DEATH(CanFrame::Classic(0x800, Bytes(1)), "id out of range");
}

TEST(CanFrameDeathTest, FdRejectsInvalidLength) {
  EXPECT_DEATH(CanFrame::Fd(0x10, Bytes(13), true), "payload length");
}

// ---- validation ----

TEST(ValidateFrameTest, AcceptsFactoryFrames) {
  EXPECT_TRUE(ValidateFrame(CanFrame::Classic(0x7FF, Bytes(8))).ok());
  EXPECT_TRUE(ValidateFrame(CanFrame::ClassicExtended(0x1FFFFFFF, Bytes(0))).ok());
  EXPECT_TRUE(ValidateFrame(CanFrame::Fd(0x1, Bytes(64), true)).ok());
  EXPECT_TRUE(ValidateFrame(CanFrame::Remote(0x1, 8, true)).ok());
  EXPECT_TRUE(ValidateFrame(CanFrame::ErrorFrame(0x4, {})).ok());
}

// IsValidFrame is ValidateFrame without the message: the two must agree on every kind of frame,
// valid or not.
TEST(ValidateFrameTest, IsValidFrameAgreesWithValidateFrame) {
  std::vector<CanFrame> frames = {CanFrame::Classic(0x7FF, Bytes(8)),
                                  CanFrame::ClassicExtended(0x1FFFFFFF, Bytes(0)),
                                  CanFrame::Fd(0x1, Bytes(64), true),
                                  CanFrame::Remote(0x1, 8, true), CanFrame::ErrorFrame(0x4, {})};
  const auto mutated = [&](auto change) {
    CanFrame frame = CanFrame::Classic(0x123, Bytes(8));
    change(frame);
    frames.push_back(frame);
  };
  mutated([](CanFrame& f) { f.id = 0x800; });
  mutated([](CanFrame& f) { f.extended = true, f.id = 0x20000000; });
  mutated([](CanFrame& f) { f.length = 9; });
  mutated([](CanFrame& f) { f.length = 65; });
  mutated([](CanFrame& f) { f.fd = true, f.length = 13; });
  mutated([](CanFrame& f) { f.fd = true, f.remote = true; });
  mutated([](CanFrame& f) { f.bitrate_switch = true; });
  mutated([](CanFrame& f) { f.error_state_indicator = true; });
  mutated([](CanFrame& f) { f.error = true, f.extended = true; });
  mutated([](CanFrame& f) { f.error = true, f.length = 9; });
  mutated([](CanFrame& f) { f.error = true, f.id = 0x20000000; });

  int valid = 0;
  for (const CanFrame& frame : frames) {
    EXPECT_EQ(IsValidFrame(frame), ValidateFrame(frame).ok()) << frame;
    valid += IsValidFrame(frame) ? 1 : 0;
  }
  EXPECT_EQ(valid, 5);  // the factory frames only
}

TEST(ValidateFrameTest, RejectsStandardIdAbove11Bits) {
  CanFrame frame;
  frame.id = 0x800;

  const Result<void> result = ValidateFrame(frame);

  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("standard id 0x800"), std::string::npos);
}

TEST(ValidateFrameTest, RejectsExtendedIdAbove29Bits) {
  CanFrame frame;
  frame.extended = true;
  frame.id = 0x20000000;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

TEST(ValidateFrameTest, RejectsClassicLongerThanEight) {
  CanFrame frame;
  frame.length = 12;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

TEST(ValidateFrameTest, RejectsFdWithInvalidLength) {
  CanFrame frame;
  frame.fd = true;
  frame.length = 13;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

TEST(ValidateFrameTest, RejectsRemoteFd) {
  CanFrame frame;
  frame.fd = true;
  frame.remote = true;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

TEST(ValidateFrameTest, RejectsBitrateSwitchOnClassic) {
  CanFrame frame;
  frame.bitrate_switch = true;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

TEST(ValidateFrameTest, RejectsExtendedErrorFrame) {
  CanFrame frame = CanFrame::ErrorFrame(0x4, {});
  frame.extended = true;

  EXPECT_FALSE(ValidateFrame(frame).ok());
}

// ---- wire timing ----

TEST(FrameBitsTest, StandardEightByteFrameIs111BitsPlus24WorstCaseStuffBits) {
  // 98 stuffable bits (SOF..CRC) get floor(97 / 4) = 24 stuff bits; 13 tail bits are unstuffed.
  const FrameBitCount bits = CountFrameBits(CanFrame::Classic(0x123, Bytes(8)));

  EXPECT_EQ(bits.nominal_bits, 111 + 24);
  EXPECT_EQ(bits.data_bits, 0);
}

TEST(FrameBitsTest, ExtendedEightByteFrameIs131BitsPlus29StuffBits) {
  const FrameBitCount bits = CountFrameBits(CanFrame::ClassicExtended(0x123, Bytes(8)));

  EXPECT_EQ(bits.nominal_bits, 131 + 29);
}

TEST(FrameBitsTest, RemoteFrameCarriesNoDataBits) {
  const FrameBitCount remote = CountFrameBits(CanFrame::Remote(0x123, 8, false));
  const FrameBitCount empty = CountFrameBits(CanFrame::Classic(0x123, Bytes(0)));

  EXPECT_EQ(remote.nominal_bits, empty.nominal_bits);
  EXPECT_EQ(empty.nominal_bits, 47 + 8);
}

TEST(FrameBitsTest, FdWithBitrateSwitchSplitsPhases) {
  // Nominal: 17 arbitration + 4 stuff + 12 tail. Data: ESI+DLC (5) + 512 data + 129 stuff +
  // 33 CRC field (stuff count, CRC-21, fixed stuff bits, delimiter).
  const FrameBitCount bits = CountFrameBits(CanFrame::Fd(0x123, Bytes(64), true));

  EXPECT_EQ(bits.nominal_bits, 33);
  EXPECT_EQ(bits.data_bits, 679);
}

TEST(FrameBitsTest, FdWithoutBitrateSwitchIsAllNominal) {
  const FrameBitCount bits = CountFrameBits(CanFrame::Fd(0x123, Bytes(64), false));

  EXPECT_EQ(bits.nominal_bits, 33 + 679);
  EXPECT_EQ(bits.data_bits, 0);
}

TEST(FrameDurationTest, StandardEightBytesAtOneMegabitIsWorstCase135Us) {
  const std::int64_t duration_ns =
      FrameDurationNs(CanFrame::Classic(0x123, Bytes(8)), 1'000'000, 1'000'000);

  EXPECT_EQ(duration_ns, 135'000);
  EXPECT_GE(duration_ns, 111'000);
}

TEST(FrameDurationTest, ScalesWithNominalBitrate) {
  EXPECT_EQ(FrameDurationNs(CanFrame::Classic(0x123, Bytes(8)), 500'000, 1'000'000), 270'000);
}

TEST(FrameDurationTest, FdDataPhaseRunsAtDataBitrate) {
  const std::int64_t duration_ns =
      FrameDurationNs(CanFrame::Fd(0x123, Bytes(64), true), 1'000'000, 5'000'000);

  EXPECT_EQ(duration_ns, 33 * 1'000 + 679 * 200);
}

TEST(FrameDurationTest, RoundsPartialNanosecondsUp) {
  // 23 error-frame bits at 3 Mbit/s = 7666.67 ns.
  EXPECT_EQ(FrameDurationNs(CanFrame::ErrorFrame(0x4, {}), 3'000'000, 3'000'000), 7'667);
}

}  // namespace
}  // namespace hilrig::rig
