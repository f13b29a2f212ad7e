// The fast candump line writer must give the same bytes as the writer it replaced. That writer is
// copied below as the oracle (the one place a copy is kept: it pins the old output) and both are
// run on a few thousand varied frames of every kind.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <string_view>

#include "rig/can_bus.h"
#include "rig/candump_log.h"

namespace hilrig::rig {
namespace {

// ---- the oracle: rig/candump_log.cc's formatting as of 5e31f0d ----
namespace oracle {

constexpr char kHexDigits[] = "0123456789ABCDEF";
constexpr std::uint8_t kFdFlagBrs = 0x1;
constexpr std::uint8_t kFdFlagEsi = 0x2;
constexpr std::int64_t kNsPerS = 1'000'000'000;
constexpr std::int64_t kNsPerUs = 1'000;
constexpr std::size_t kMaxFrameChars = 8 + 2 + 1 + 2 * 64;
constexpr std::size_t kMaxTimestampChars = 1 + 19 + 1 + 6 + 1;

char* WriteHex(std::uint32_t value, int digits, char* out) {
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) {
    *out++ = kHexDigits[(value >> shift) & 0xF];
  }
  return out;
}

char* WriteDecimal(std::uint64_t value, int min_digits, char* out) {
  std::array<char, 20> reversed;
  int count = 0;
  do {
    reversed[count++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  for (int i = count; i < min_digits; ++i) *out++ = '0';
  while (count > 0) *out++ = reversed[--count];
  return out;
}

char* WriteTimestamp(std::int64_t time_ns, char* out) {
  *out++ = '(';
  out = WriteDecimal(static_cast<std::uint64_t>(time_ns / kNsPerS), 10, out);
  *out++ = '.';
  out = WriteDecimal(static_cast<std::uint64_t>((time_ns % kNsPerS) / kNsPerUs), 6, out);
  *out++ = ')';
  return out;
}

char* WriteId(const CanFrame& frame, char* out) {
  if (frame.error) return WriteHex(frame.id | kCanErrFlag, 8, out);
  return WriteHex(frame.id, frame.extended ? 8 : 3, out);
}

char* WriteFrame(const CanFrame& frame, char* out) {
  out = WriteId(frame, out);
  *out++ = '#';
  if (frame.remote) {
    *out++ = 'R';
    if (frame.length > 0) *out++ = kHexDigits[frame.length];
    return out;
  }
  if (frame.fd) {
    *out++ = '#';
    *out++ = kHexDigits[(frame.bitrate_switch ? kFdFlagBrs : 0) |
                        (frame.error_state_indicator ? kFdFlagEsi : 0)];
  }
  for (const std::uint8_t byte : frame.payload()) {
    *out++ = kHexDigits[byte >> 4];
    *out++ = kHexDigits[byte & 0xF];
  }
  return out;
}

void AppendCandumpLine(const TimedCanFrame& frame, std::string_view interface_name,
                       std::string& out, DirectionMark mark) {
  std::array<char, kMaxTimestampChars + 1> stamp;
  char* stamp_end = WriteTimestamp(frame.time_ns, stamp.data());
  *stamp_end++ = ' ';
  out.append(stamp.data(), stamp_end);
  out.append(interface_name);
  std::array<char, 1 + kMaxFrameChars + 2> text;
  char* text_end = text.data();
  *text_end++ = ' ';
  text_end = WriteFrame(frame.frame, text_end);
  if (mark == DirectionMark::kRxTx) {
    *text_end++ = ' ';
    *text_end++ = frame.tx_echo ? 'T' : 'R';
  }
  out.append(text.data(), text_end);
}

}  // namespace oracle

// ---- varied frames ----

constexpr std::array<std::size_t, 16> kFdLengths = {0, 1,  2,  3,  4,  5,  6,  7,
                                                    8, 12, 16, 20, 24, 32, 48, 64};

std::vector<std::uint8_t> RandomBytes(std::mt19937_64& rng, std::size_t count) {
  std::vector<std::uint8_t> bytes(count);
  for (auto& byte : bytes) byte = static_cast<std::uint8_t>(rng());
  return bytes;
}

// One frame of kind `kind` (0 standard, 1 extended, 2 remote, 3 FD, 4 FD extended, 5 error).
CanFrame RandomFrame(std::mt19937_64& rng, int kind) {
  const auto dlc = static_cast<std::size_t>(rng() % 9);
  switch (kind) {
    case 0:
      return CanFrame::Classic(static_cast<std::uint32_t>(rng() % (kMaxStandardId + 1)),
                               RandomBytes(rng, dlc));
    case 1:
      return CanFrame::ClassicExtended(static_cast<std::uint32_t>(rng() % (kMaxExtendedId + 1)),
                                       RandomBytes(rng, dlc));
    case 2: {
      const bool extended = rng() % 2 == 0;
      const std::uint32_t max_id = extended ? kMaxExtendedId : kMaxStandardId;
      return CanFrame::Remote(static_cast<std::uint32_t>(rng() % (max_id + 1)),
                              static_cast<std::uint8_t>(dlc), extended);
    }
    case 3:
    case 4: {
      const std::size_t length = kFdLengths[rng() % kFdLengths.size()];
      const bool extended = kind == 4;
      const std::uint32_t max_id = extended ? kMaxExtendedId : kMaxStandardId;
      const auto id = static_cast<std::uint32_t>(rng() % (max_id + 1));
      CanFrame frame = extended ? CanFrame::FdExtended(id, RandomBytes(rng, length), rng() % 2)
                                : CanFrame::Fd(id, RandomBytes(rng, length), rng() % 2);
      frame.error_state_indicator = rng() % 2 == 0;
      return frame;
    }
    default: {
      std::array<std::uint8_t, CanFrame::kMaxClassicPayload> data;
      for (auto& byte : data) byte = static_cast<std::uint8_t>(rng());
      CanFrame frame =
          CanFrame::ErrorFrame(static_cast<std::uint32_t>(rng() % (kMaxExtendedId + 1)), data);
      frame.length = static_cast<std::uint8_t>(dlc);  // shorter error frames are valid too
      return frame;
    }
  }
}

// Timestamps from 0 over the epochs logs use to the largest int64: every digit count and the
// zero padding of seconds and microseconds.
std::int64_t RandomTimeNs(std::mt19937_64& rng) {
  switch (rng() % 4) {
    case 0:
      return static_cast<std::int64_t>(rng() % 2'000'000'000);  // under two seconds
    case 1:
      return 1'700'000'000'000'000'000 + static_cast<std::int64_t>(rng() % 1'000'000'000'000);
    case 2:
      return static_cast<std::int64_t>(rng() >> 1);  // anywhere in the int64 range
    default:
      return static_cast<std::int64_t>(rng() % 100'000) * 1'000'000'000;  // whole seconds
  }
}

TEST(CandumpLineOracleTest, EveryFrameKindGivesTheOldBytes) {
  std::mt19937_64 rng(20261121);
  int compared = 0;
  for (int i = 0; i < 6000; ++i) {
    TimedCanFrame frame{RandomFrame(rng, i % 6), RandomTimeNs(rng)};
    frame.tx_echo = rng() % 2 == 0;
    const DirectionMark mark = rng() % 2 == 0 ? DirectionMark::kNone : DirectionMark::kRxTx;
    const std::string_view name = i % 3 == 0 ? "can0" : (i % 3 == 1 ? "vcan12" : "a_long_if_name");
    std::string expected = "prefix ";
    oracle::AppendCandumpLine(frame, name, expected, mark);
    std::string actual = "prefix ";
    AppendCandumpLine(frame, name, actual, mark);
    ASSERT_EQ(actual, expected) << "frame " << i;
    ++compared;
  }
  EXPECT_EQ(compared, 6000);
}

TEST(CandumpLineOracleTest, WriterGivesTheOldLines) {
  std::mt19937_64 rng(7);
  std::ostringstream written;
  CandumpLogWriter writer(written, "can1", DirectionMark::kRxTx);
  std::string expected;
  for (int i = 0; i < 3000; ++i) {
    TimedCanFrame frame{RandomFrame(rng, i % 6), RandomTimeNs(rng)};
    frame.tx_echo = i % 5 == 0;
    writer.Write(frame);
    oracle::AppendCandumpLine(frame, "can1", expected, DirectionMark::kRxTx);
    expected.push_back('\n');
  }
  EXPECT_EQ(written.str(), expected);
}

TEST(CandumpLineOracleTest, EdgeTimestampsGiveTheOldBytes) {
  const CanFrame frame = CanFrame::Classic(0x7FF, std::array<std::uint8_t, 1>{0x0F});
  for (const std::int64_t time_ns :
       {std::int64_t{0}, std::int64_t{999}, std::int64_t{1'000}, std::int64_t{999'999'999},
        std::int64_t{1'000'000'000}, std::int64_t{9'999'999'999'999'999},
        std::numeric_limits<std::int64_t>::max()}) {
    std::string expected;
    oracle::AppendCandumpLine({frame, time_ns}, "can0", expected, DirectionMark::kNone);
    EXPECT_EQ(FormatCandumpLine({frame, time_ns}, "can0"), expected) << time_ns;
  }
}

}  // namespace
}  // namespace hilrig::rig
