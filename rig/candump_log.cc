#include "rig/candump_log.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <limits>

#include "rig/check.h"
#include "rig/decimal_digits.h"

namespace hilrig::rig {
namespace {

constexpr char kHexDigits[] = "0123456789ABCDEF";
constexpr std::uint8_t kFdFlagBrs = 0x1;
constexpr std::uint8_t kFdFlagEsi = 0x2;
constexpr std::int64_t kNsPerS = 1'000'000'000;
constexpr std::int64_t kNsPerUs = 1'000;
constexpr std::int64_t kMaxSeconds = (std::numeric_limits<std::int64_t>::max() - kNsPerS) / kNsPerS;

// ---- formatting ----
// A line is written into a char buffer with room for the longest line, without any per-character
// string append, division loop or format call: a log line is written per frame in the lockstep
// loop (seven frames per millisecond in the busiest scenes).

// The longest frame text: an 8-digit id, "##", the flags nibble and 64 data bytes.
constexpr std::size_t kMaxFrameChars = 8 + 2 + 1 + 2 * 64;
// "(" + 10 digits of seconds (an int64 of nanoseconds holds fewer than 10^10 s) + "." + 6 digits
// + ")".
constexpr std::size_t kTimestampChars = 1 + 10 + 1 + 6 + 1;
static_assert(std::numeric_limits<std::int64_t>::max() / kNsPerS < 10'000'000'000);

// The longest line for an interface name of `name_chars`: timestamp, the name between two spaces,
// the frame and " T".
constexpr std::size_t MaxLineChars(std::size_t name_chars) {
  return kTimestampChars + 1 + name_chars + 1 + kMaxFrameChars + 2;
}

// "00".."FF": two characters per table look-up (the decimal pairs are rig/decimal_digits.h).
constexpr std::array<char, 512> kHexPairs = [] {
  std::array<char, 512> pairs{};
  for (int i = 0; i < 256; ++i) {
    pairs[2 * i] = kHexDigits[i >> 4];
    pairs[2 * i + 1] = kHexDigits[i & 0xF];
  }
  return pairs;
}();

char* WriteHexByte(std::uint32_t byte, char* out) {
  std::memcpy(out, &kHexPairs[2 * byte], 2);
  return out + 2;
}

// `value` < 10^4 as exactly four digits; 32-bit divisions by constants are a multiply and a shift.
char* WriteFourDigits(std::uint32_t value, char* out) {
  out = WriteTwoDecimalDigits(value / 100, out);
  return WriteTwoDecimalDigits(value % 100, out);
}

// "(SSSSSSSSSS.": the seconds zero-padded to 10 digits, in 32-bit pieces.
constexpr std::size_t kSecondsPartChars = 1 + 10 + 1;
char* WriteSecondsPart(std::uint64_t seconds, char* out) {
  const auto seconds_high = static_cast<std::uint32_t>(seconds / 100'000'000);  // < 100
  const auto seconds_low = static_cast<std::uint32_t>(seconds % 100'000'000);
  *out++ = '(';
  out = WriteTwoDecimalDigits(seconds_high, out);
  out = WriteFourDigits(seconds_low / 10'000, out);
  out = WriteFourDigits(seconds_low % 10'000, out);
  *out++ = '.';
  return out;
}

// "UUUUUU)": the microseconds within the second, zero-padded to 6 digits.
char* WriteMicrosPart(std::uint32_t micros, char* out) {
  out = WriteTwoDecimalDigits(micros / 10'000, out);
  out = WriteFourDigits(micros % 10'000, out);
  *out++ = ')';
  return out;
}

struct SplitTime {
  std::uint64_t seconds;
  std::uint32_t micros;
};

// One 64-bit division splits the seconds.
SplitTime SplitTimestamp(std::int64_t time_ns) {
  HILRIG_CHECK(time_ns >= 0, "candump timestamps cannot be negative");
  const auto ns = static_cast<std::uint64_t>(time_ns);
  return {ns / kNsPerS, static_cast<std::uint32_t>((ns % kNsPerS) / kNsPerUs)};
}

// Exactly kTimestampChars characters.
char* WriteTimestamp(std::int64_t time_ns, char* out) {
  const SplitTime time = SplitTimestamp(time_ns);
  return WriteMicrosPart(time.micros, WriteSecondsPart(time.seconds, out));
}

// "000#".."7FF#": a standard id's text and the separator, one table look-up per line.
constexpr std::size_t kStandardIdChars = 4;
constexpr std::array<char, (kMaxStandardId + 1)* kStandardIdChars> kStandardIdTexts = [] {
  std::array<char, (kMaxStandardId + 1) * kStandardIdChars> texts{};
  for (std::uint32_t id = 0; id <= kMaxStandardId; ++id) {
    texts[kStandardIdChars * id] = kHexDigits[id >> 8];
    texts[kStandardIdChars * id + 1] = kHexDigits[(id >> 4) & 0xF];
    texts[kStandardIdChars * id + 2] = kHexDigits[id & 0xF];
    texts[kStandardIdChars * id + 3] = '#';
  }
  return texts;
}();

// A standard id has 3 hex digits (11 bits), an extended or error id 8; then '#'. The frame is
// valid, so a standard id is at most kMaxStandardId.
char* WriteIdAndSeparator(const CanFrame& frame, char* out) {
  if (!frame.error && !frame.extended) {
    std::memcpy(out, &kStandardIdTexts[kStandardIdChars * frame.id], kStandardIdChars);
    return out + kStandardIdChars;
  }
  const std::uint32_t id = frame.error ? frame.id | kCanErrFlag : frame.id;
  for (int shift = 24; shift >= 0; shift -= 8) out = WriteHexByte((id >> shift) & 0xFF, out);
  *out++ = '#';
  return out;
}

// The frame is valid (CheckLoggable), so its length fits the data array.
char* WriteFrame(const CanFrame& frame, char* out) {
  out = WriteIdAndSeparator(frame, out);
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
  if (frame.length <= CanFrame::kMaxClassicPayload) {
    // All eight bytes without a loop, then only the frame's length counts: the line buffer has
    // room for 64 bytes and what follows the data is written over the rest.
    for (std::size_t i = 0; i < CanFrame::kMaxClassicPayload; ++i) {
      WriteHexByte(frame.data[i], out + 2 * i);
    }
    return out + 2 * std::size_t{frame.length};
  }
  for (std::size_t i = 0; i < frame.length; ++i) out = WriteHexByte(frame.data[i], out);
  return out;
}

// Out of line, so that the message's construction does not keep the check below from being
// inlined into the per-frame path.
[[noreturn, gnu::noinline]] void FailUnloggable(const CanFrame& frame) {
  const std::string message =
      "cannot log an invalid frame: " + ValidateFrame(frame).error().message;
  check_internal::Fail("IsValidFrame(frame.frame)", message, HILRIG_SOURCE_FILE, __LINE__);
}

void CheckLoggable(const TimedCanFrame& frame) {
  if (!IsValidFrame(frame.frame)) [[unlikely]]
    FailUnloggable(frame.frame);
}

// " name ": the timestamp is fixed-width, so in a reused line buffer this never moves.
char* WriteInterfaceName(std::string_view interface_name, char* out) {
  *out++ = ' ';
  std::memcpy(out, interface_name.data(), interface_name.size());
  out += interface_name.size();
  *out++ = ' ';
  return out;
}

// What follows the interface name: the frame and the direction token.
char* WriteLineTail(const TimedCanFrame& frame, DirectionMark mark, char* out) {
  out = WriteFrame(frame.frame, out);
  if (mark == DirectionMark::kRxTx) {
    *out++ = ' ';
    *out++ = frame.tx_echo ? 'T' : 'R';
  }
  return out;
}

// The whole line (without newline) at `out`, which has room for MaxLineChars(name's size).
char* WriteLine(const TimedCanFrame& frame, std::string_view interface_name, DirectionMark mark,
                char* out) {
  CheckLoggable(frame);
  out = WriteTimestamp(frame.time_ns, out);
  out = WriteInterfaceName(interface_name, out);
  return WriteLineTail(frame, mark, out);
}

// ---- parsing ----

int Nibble(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool AllDigits(std::string_view text) {
  return !text.empty() &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// Fills `tokens` with whitespace-separated fields; returns how many there were (may exceed the
// array size, in which case the extra ones are not stored).
std::size_t SplitFields(std::string_view line, std::span<std::string_view> tokens) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    if (i == line.size()) return count;
    const std::size_t begin = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (count < tokens.size()) tokens[count] = line.substr(begin, i - begin);
    ++count;
  }
}

Result<std::int64_t> ParseTimestampNs(std::string_view token) {
  if (token.size() < 3 || token.front() != '(' || token.back() != ')') {
    return MakeError("timestamp must look like (seconds.microseconds)");
  }
  const std::string_view inner = token.substr(1, token.size() - 2);
  const std::size_t dot = inner.find('.');
  if (dot == std::string_view::npos) return MakeError("timestamp has no '.'");
  const std::string_view seconds_text = inner.substr(0, dot);
  const std::string_view micros_text = inner.substr(dot + 1);
  if (!AllDigits(seconds_text)) return MakeError("timestamp seconds are not decimal digits");
  if (micros_text.size() != 6 || !AllDigits(micros_text)) {
    return MakeError("timestamp needs exactly 6 microsecond digits");
  }
  std::int64_t seconds = 0;
  std::int64_t micros = 0;
  const auto end = seconds_text.data() + seconds_text.size();
  if (std::from_chars(seconds_text.data(), end, seconds).ec != std::errc() ||
      seconds > kMaxSeconds) {
    return MakeError("timestamp seconds out of range");
  }
  std::from_chars(micros_text.data(), micros_text.data() + micros_text.size(), micros);
  return seconds * kNsPerS + micros * kNsPerUs;
}

Result<void> ParseId(std::string_view text, CanFrame& frame) {
  if (text.size() != 3 && text.size() != 8) {
    return MakeError("id must be 3 (standard) or 8 (extended) hex digits");
  }
  std::uint32_t value = 0;
  for (const char c : text) {
    const int nibble = Nibble(c);
    if (nibble < 0) return MakeError("id is not hexadecimal");
    value = (value << 4) | static_cast<std::uint32_t>(nibble);
  }
  // Like can-utils: 8 digits mean an extended id unless CAN_ERR_FLAG marks an error frame.
  frame.error = text.size() == 8 && (value & kCanErrFlag) != 0;
  frame.extended = text.size() == 8 && !frame.error;
  frame.id = frame.error ? value & ~kCanErrFlag : value;
  return {};
}

Result<void> ParseRemoteLength(std::string_view text, CanFrame& frame) {
  frame.remote = true;
  if (text.empty()) return {};
  const int length = text.size() == 1 ? Nibble(text[0]) : -1;
  if (length < 0 || length > static_cast<int>(CanFrame::kMaxClassicPayload)) {
    return MakeError("remote frame length must be a single digit 0..8");
  }
  frame.length = static_cast<std::uint8_t>(length);
  return {};
}

Result<void> ParseData(std::string_view text, CanFrame& frame) {
  std::size_t length = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == '.') {
      ++i;
      continue;
    }
    if (i + 1 >= text.size()) return MakeError("data has an odd number of hex digits");
    const int high = Nibble(text[i]);
    const int low = Nibble(text[i + 1]);
    if (high < 0 || low < 0) return MakeError("data is not hexadecimal");
    if (length == CanFrame::kMaxFdPayload) return MakeError("data longer than 64 bytes");
    frame.data[length++] = static_cast<std::uint8_t>((high << 4) | low);
    i += 2;
  }
  frame.length = static_cast<std::uint8_t>(length);
  return {};
}

Result<void> ParseFdFlagsAndData(std::string_view text, CanFrame& frame) {
  frame.fd = true;
  const int flags = text.empty() ? -1 : Nibble(text[0]);
  if (flags < 0) return MakeError("CAN FD frame needs a hex flags digit after '##'");
  frame.bitrate_switch = (flags & kFdFlagBrs) != 0;
  frame.error_state_indicator = (flags & kFdFlagEsi) != 0;
  return ParseData(text.substr(1), frame);
}

// What follows the id's '#': "R[len]", "#<flags><data>" (FD) or "<data>".
Result<void> ParseBody(std::string_view text, CanFrame& frame) {
  if (!text.empty() && (text[0] == 'R' || text[0] == 'r')) {
    return ParseRemoteLength(text.substr(1), frame);
  }
  if (!text.empty() && text[0] == '#') return ParseFdFlagsAndData(text.substr(1), frame);
  return ParseData(text, frame);
}

Result<CanFrame> ParseFrame(std::string_view text) {
  const std::size_t hash = text.find('#');
  if (hash == std::string_view::npos) return MakeError("frame has no '#' after the id");
  CanFrame frame;
  if (Result<void> id = ParseId(text.substr(0, hash), frame); !id) return id.error();
  if (Result<void> body = ParseBody(text.substr(hash + 1), frame); !body) return body.error();
  if (Result<void> valid = ValidateFrame(frame); !valid) return valid.error();
  return frame;
}

Result<std::pair<TimedCanFrame, std::string>> ParseFields(std::string_view line) {
  std::array<std::string_view, 4> fields;
  const std::size_t count = SplitFields(line, fields);
  if (count < 3) return MakeError("expected '(seconds.microseconds) interface frame'");
  if (count > 4 || (count == 4 && fields[3] != "R" && fields[3] != "T")) {
    return MakeError("unexpected text after the frame");
  }
  Result<std::int64_t> time_ns = ParseTimestampNs(fields[0]);
  if (!time_ns) return time_ns.error();
  Result<CanFrame> frame = ParseFrame(fields[2]);
  if (!frame) return frame.error();
  TimedCanFrame timed{frame.value(), time_ns.value()};
  timed.tx_echo = count == 4 && fields[3] == "T";
  return std::pair{timed, std::string(fields[1])};
}

}  // namespace

void AppendCandumpLine(const TimedCanFrame& frame, std::string_view interface_name,
                       std::string& out, DirectionMark mark) {
  const std::size_t start = out.size();
  out.resize(start + MaxLineChars(interface_name.size()));
  const char* end = WriteLine(frame, interface_name, mark, out.data() + start);
  out.resize(static_cast<std::size_t>(end - out.data()));
}

std::string FormatCandumpLine(const TimedCanFrame& frame, std::string_view interface_name) {
  std::string line;
  AppendCandumpLine(frame, interface_name, line);
  return line;
}

Result<std::pair<TimedCanFrame, std::string>> ParseCandumpLine(std::string_view line) {
  while (!line.empty() && IsSpace(line.back())) line.remove_suffix(1);
  auto parsed = ParseFields(line);
  // A log may come from anywhere: the message says what is wrong, never what the line holds.
  if (!parsed) return MakeError("bad candump line: " + parsed.error().message);
  return parsed;
}

// At least this many characters of prefix_ are copied to start each line, a constant that
// compiles to two vector moves: the prefix itself for names of up to 11 characters, the whole
// prefix byte by byte for longer ones. Each line's buffer has room for it.
constexpr std::size_t kPrefixCopyChars = 32;
static_assert(kPrefixCopyChars <= MaxLineChars(0));

CandumpLogWriter::CandumpLogWriter(std::ostream& out, std::string interface_name,
                                   DirectionMark mark)
    : out_(out),
      interface_name_(std::move(interface_name)),
      mark_(mark),
      prefix_(std::max(kPrefixCopyChars, kTimestampChars + 2 + interface_name_.size()), '\0') {
  WriteInterfaceName(interface_name_, prefix_.data() + kTimestampChars);
}

// Straight into the stream's buffer: ostream::write would build a sentry (state test, tie flush)
// per call for a stream nothing else writes to meanwhile. The stream's state still says whether
// the lines went out, set as ostream::write sets it: failbit for a stream that was not good,
// badbit for a short write; a unitbuf stream is still flushed.
// Each line starts as a copy of the prefix (the seconds digits change once per second); only the
// microseconds and what follows the name are written per frame.
void CandumpLogWriter::WriteAll(std::span<const TimedCanFrame> frames) {
  const std::size_t prefix_chars = kTimestampChars + 2 + interface_name_.size();
  const std::size_t line_chars = MaxLineChars(interface_name_.size()) + 1;  // and the newline
  if (lines_.size() < frames.size() * line_chars) lines_.resize(frames.size() * line_chars);
  char* const begin = lines_.data();
  char* end = begin;
  for (const TimedCanFrame& frame : frames) {
    CheckLoggable(frame);
    const SplitTime time = SplitTimestamp(frame.time_ns);
    if (time.seconds != seconds_in_prefix_) {
      WriteSecondsPart(time.seconds, prefix_.data());
      seconds_in_prefix_ = time.seconds;
    }
    if (prefix_chars <= kPrefixCopyChars) {
      std::memcpy(end, prefix_.data(), kPrefixCopyChars);
    } else {
      std::memcpy(end, prefix_.data(), prefix_chars);
    }
    WriteMicrosPart(time.micros, end + kSecondsPartChars);
    end = WriteLineTail(frame, mark_, end + prefix_chars);
    *end++ = '\n';
  }
  const std::streamsize length = end - begin;
  if (!out_.good()) {
    out_.setstate(std::ios_base::failbit);
  } else if (out_.rdbuf()->sputn(begin, length) != length) {
    out_.setstate(std::ios_base::badbit);
  } else if ((out_.flags() & std::ios_base::unitbuf) != 0) {
    out_.flush();  // what the sentry does on leaving, for streams like std::cerr
  }
  frames_written_ += frames.size();
}

std::uint64_t CandumpLogWriter::frames_written() const { return frames_written_; }

}  // namespace hilrig::rig
