#include "rig/candump_log.h"

#include <gtest/gtest.h>

#include <array>
#include <sstream>
#include <string>
#include <vector>

namespace hilrig::rig {
namespace {

constexpr std::int64_t kTimeNs = 1'700'000'000'123'456'789;  // logs keep microseconds only
constexpr std::int64_t kLoggedTimeNs = 1'700'000'000'123'456'000;

TimedCanFrame At(const CanFrame& frame, std::int64_t time_ns = kLoggedTimeNs) {
  return {frame, time_ns};
}

std::vector<std::uint8_t> Counting(std::size_t count) {
  std::vector<std::uint8_t> bytes(count);
  for (std::size_t i = 0; i < count; ++i) bytes[i] = static_cast<std::uint8_t>(0x10 + i);
  return bytes;
}

CanFrame StandardFrame() {
  return CanFrame::Classic(0x123, std::array<std::uint8_t, 4>{0xDE, 0xAD, 0xBE, 0xEF});
}
CanFrame ExtendedFrame() {
  return CanFrame::ClassicExtended(0x1ABCDEF, std::array<std::uint8_t, 2>{0x00, 0xFF});
}
CanFrame FdBrsFrame() { return CanFrame::Fd(0x123, Counting(12), /*bitrate_switch=*/true); }
CanFrame ControllerErrorFrame() {
  return CanFrame::ErrorFrame(0x4, {0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});
}

// ---- exact output ----

TEST(FormatCandumpLineTest, StandardFrame) {
  EXPECT_EQ(FormatCandumpLine(At(StandardFrame(), kTimeNs), "can0"),
            "(1700000000.123456) can0 123#DEADBEEF");
}

TEST(FormatCandumpLineTest, PadsSecondsToTenDigits) {
  EXPECT_EQ(FormatCandumpLine(At(CanFrame::Classic(0x7, {}), 1'500'000), "vcan1"),
            "(0000000000.001500) vcan1 007#");
}

TEST(FormatCandumpLineTest, ExtendedFrameUsesEightDigits) {
  EXPECT_EQ(FormatCandumpLine(At(ExtendedFrame()), "can0"),
            "(1700000000.123456) can0 01ABCDEF#00FF");
}

TEST(FormatCandumpLineTest, RemoteFrameWithoutLength) {
  EXPECT_EQ(FormatCandumpLine(At(CanFrame::Remote(0x123, 0, false)), "can0"),
            "(1700000000.123456) can0 123#R");
}

TEST(FormatCandumpLineTest, RemoteFrameWithLength) {
  EXPECT_EQ(FormatCandumpLine(At(CanFrame::Remote(0x123, 5, false)), "can0"),
            "(1700000000.123456) can0 123#R5");
}

TEST(FormatCandumpLineTest, FdFrameWithBitrateSwitch) {
  EXPECT_EQ(FormatCandumpLine(At(FdBrsFrame()), "can0"),
            "(1700000000.123456) can0 123##1101112131415161718191A1B");
}

TEST(FormatCandumpLineTest, FdFrameWithErrorStateIndicator) {
  CanFrame frame = CanFrame::Fd(0x42, {}, /*bitrate_switch=*/true);
  frame.error_state_indicator = true;

  EXPECT_EQ(FormatCandumpLine(At(frame), "can0"), "(1700000000.123456) can0 042##3");
}

TEST(FormatCandumpLineTest, ErrorFrameCarriesErrFlagAndWholeData) {
  EXPECT_EQ(FormatCandumpLine(At(ControllerErrorFrame()), "can0"),
            "(1700000000.123456) can0 20000004#0004000000000000");
}

// ---- round trip ----

class CandumpRoundTripTest : public testing::TestWithParam<CanFrame> {};

TEST_P(CandumpRoundTripTest, ParseInvertsFormat) {
  const TimedCanFrame original = At(GetParam());
  const std::string line = FormatCandumpLine(original, "vcan0");

  const auto parsed = ParseCandumpLine(line);

  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed.value().first, original);
  EXPECT_EQ(parsed.value().second, "vcan0");
}

INSTANTIATE_TEST_SUITE_P(AllFrameKinds, CandumpRoundTripTest,
                         testing::Values(StandardFrame(), ExtendedFrame(),
                                         CanFrame::Remote(0x123, 0, false),
                                         CanFrame::Remote(0x123, 8, false),
                                         CanFrame::Remote(0x1ABCDEF, 3, true), FdBrsFrame(),
                                         CanFrame::FdExtended(0x1ABCDEF, Counting(64), false),
                                         ControllerErrorFrame(), CanFrame::Classic(0x0, {})));

// ---- what other tools write ----

TEST(ParseCandumpLineTest, AcceptsLowercaseDotsAndNewline) {
  const auto parsed = ParseCandumpLine("(0000000001.000002) can0 1ab#de.ad\n");

  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed.value().first,
            At(CanFrame::Classic(0x1AB, std::array<std::uint8_t, 2>{0xDE, 0xAD}), 1'000'002'000));
}

TEST(ParseCandumpLineTest, IgnoresFdfFlagFromNewerKernels) {
  const auto parsed = ParseCandumpLine("(0000000001.000000) can0 123##5");

  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_TRUE(parsed.value().first.frame.fd);
  EXPECT_TRUE(parsed.value().first.frame.bitrate_switch);
  EXPECT_FALSE(parsed.value().first.frame.error_state_indicator);
}

TEST(ParseCandumpLineTest, AcceptsDirectionTokenFromCandumpX) {
  EXPECT_TRUE(ParseCandumpLine("(0000000001.000000) can0 123#00 R").ok());
}

// ---- malformed input ----

struct MalformedLine {
  const char* line;
  const char* complaint;
};

class ParseCandumpLineErrorTest : public testing::TestWithParam<MalformedLine> {};

TEST_P(ParseCandumpLineErrorTest, NamesWhatIsWrong) {
  const auto parsed = ParseCandumpLine(GetParam().line);

  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.error().message.find(GetParam().complaint), std::string::npos)
      << parsed.error().message;
}

INSTANTIATE_TEST_SUITE_P(
    Malformed, ParseCandumpLineErrorTest,
    testing::Values(MalformedLine{"", "expected '(seconds.microseconds) interface frame'"},
                    MalformedLine{"(1.000000) can0", "expected"},
                    MalformedLine{"1.000000 can0 123#00", "(seconds.microseconds)"},
                    MalformedLine{"(1.00000) can0 123#00", "6 microsecond digits"},
                    MalformedLine{"(x.000000) can0 123#00", "seconds are not decimal"},
                    MalformedLine{"(99999999999.000000) can0 123#00", "out of range"},
                    MalformedLine{"(1.000000) can0 12300", "no '#'"},
                    MalformedLine{"(1.000000) can0 1234#00", "3 (standard) or 8 (extended)"},
                    MalformedLine{"(1.000000) can0 12G#00", "id is not hexadecimal"},
                    MalformedLine{"(1.000000) can0 800#00", "standard id 0x800 out of range"},
                    MalformedLine{"(1.000000) can0 123#0", "odd number"},
                    MalformedLine{"(1.000000) can0 123#0G", "data is not hexadecimal"},
                    MalformedLine{"(1.000000) can0 123#000102030405060708", "exceeds 8"},
                    MalformedLine{"(1.000000) can0 123##100010203040506070809",
                                  "not a valid CAN FD length"},
                    MalformedLine{"(1.000000) can0 123##", "flags digit"},
                    MalformedLine{"(1.000000) can0 123#R9", "remote frame length"},
                    MalformedLine{"(1.000000) can0 123#00 junk", "unexpected text"}));

// ---- writer ----

TEST(CandumpLogWriterTest, WritesOneLinePerFrame) {
  std::ostringstream out;
  CandumpLogWriter writer(out, "vcan0");

  writer.Write(At(StandardFrame(), 1'000));
  writer.Write(At(ExtendedFrame(), 2'000'000));

  EXPECT_EQ(out.str(),
            "(0000000000.000001) vcan0 123#DEADBEEF\n"
            "(0000000000.002000) vcan0 01ABCDEF#00FF\n");
  EXPECT_EQ(writer.frames_written(), 2u);
}

// The line buffer is reused and eight data bytes are written whatever the length: a shorter
// frame after a longer one must end at its own last byte, with the direction mark after it.
TEST(CandumpLogWriterTest, AShortFrameAfterALongOneEndsAtItsOwnData) {
  std::ostringstream out;
  CandumpLogWriter writer(out, "can0", DirectionMark::kRxTx);

  writer.Write(At(CanFrame::Classic(0x7FF, Counting(8)), 1'000));
  writer.Write(At(CanFrame::Classic(0x000, Counting(1)), 2'000));
  writer.Write(At(CanFrame::Classic(0x10A, {}), 3'000));

  EXPECT_EQ(out.str(),
            "(0000000000.000001) can0 7FF#1011121314151617 R\n"
            "(0000000000.000002) can0 000#10 R\n"
            "(0000000000.000003) can0 10A# R\n");
}

// A batch is the same text as its frames written one by one, for a short interface name (whose
// prefix is copied as a fixed block) and a long one, across a second boundary.
TEST(CandumpLogWriterTest, WriteAllWritesWhatWriteWritesFrameByFrame) {
  const std::vector<TimedCanFrame> frames = {
      At(StandardFrame(), 999'999'000), At(ExtendedFrame(), 1'000'000'000),
      At(CanFrame::Classic(0x107, Counting(8)), 1'000'003'000), At(FdBrsFrame(), 2'500'000'000)};
  for (const std::string name : {"can0", "a_very_long_interface_name0"}) {
    std::ostringstream one_by_one;
    std::ostringstream batched;
    CandumpLogWriter single(one_by_one, name, DirectionMark::kRxTx);
    CandumpLogWriter batch(batched, name, DirectionMark::kRxTx);
    for (const TimedCanFrame& frame : frames) single.Write(frame);
    batch.WriteAll(std::span(frames).first(1));
    batch.WriteAll(std::span(frames).subspan(1));
    EXPECT_EQ(batched.str(), one_by_one.str()) << name;
    EXPECT_EQ(batch.frames_written(), frames.size());
    EXPECT_NE(batched.str().find(name + " 107#1011121314151617 R\n"), std::string::npos);
  }
}

// The writer keeps the seconds digits of its last line; a line in another second, earlier or
// later, must still carry its own.
TEST(CandumpLogWriterTest, EachLineCarriesItsOwnSecondsAcrossSecondBoundaries) {
  std::ostringstream out;
  CandumpLogWriter writer(out, "can0");

  writer.Write(At(StandardFrame(), 1'999'999'000));
  writer.Write(At(StandardFrame(), 2'000'000'000));
  writer.Write(At(StandardFrame(), 1'500'000'000));
  writer.Write(At(StandardFrame(), 12'345'678'901'234'567));

  EXPECT_EQ(out.str(),
            "(0000000001.999999) can0 123#DEADBEEF\n"
            "(0000000002.000000) can0 123#DEADBEEF\n"
            "(0000000001.500000) can0 123#DEADBEEF\n"
            "(0012345678.901234) can0 123#DEADBEEF\n");
}

TEST(CandumpLogWriterTest, StreamThatIsNotGoodGetsNothingAndFailbit) {
  std::ostringstream out;
  out.setstate(std::ios_base::eofbit);
  CandumpLogWriter writer(out, "can0");

  writer.Write(At(StandardFrame(), 1'000));

  EXPECT_EQ(out.str(), "");
  EXPECT_TRUE(out.fail());
}

TEST(CandumpLogWriterDeathTest, RefusesInvalidFrame) {
  std::ostringstream out;
  CandumpLogWriter writer(out);
  CanFrame invalid;
  invalid.id = 0x800;

  EXPECT_DEATH(writer.Write(At(invalid)), "invalid frame");
}

}  // namespace
}  // namespace hilrig::rig

namespace hilrig::rig {
namespace {

TEST(CandumpDirectionTest, WriterMarksTxAndRxAndParserReadsThemBack) {
  const std::uint8_t data[2] = {0xAB, 0xCD};
  TimedCanFrame sent{CanFrame::Classic(0x123, data), 1'000'000};
  sent.tx_echo = true;
  TimedCanFrame received{CanFrame::Classic(0x124, data), 2'000'000};
  std::ostringstream log;
  CandumpLogWriter writer(log, "can0", DirectionMark::kRxTx);
  writer.Write(sent);
  writer.Write(received);
  EXPECT_EQ(log.str(),
            "(0000000000.001000) can0 123#ABCD T\n(0000000000.002000) can0 124#ABCD R\n");
  const auto parsed = ParseCandumpLine("(0000000000.001000) can0 123#ABCD T");
  ASSERT_TRUE(parsed.ok());
  EXPECT_TRUE(parsed.value().first.tx_echo);
  EXPECT_FALSE(ParseCandumpLine("(0000000000.001000) can0 123#ABCD R").value().first.tx_echo);
}

}  // namespace
}  // namespace hilrig::rig
