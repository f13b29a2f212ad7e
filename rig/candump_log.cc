#include "rig/candump_log.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>

#include "rig/check.h"

namespace hilrig::rig {
namespace {

constexpr char kHexDigits[] = "0123456789ABCDEF";
constexpr std::uint8_t kFdFlagBrs = 0x1;
constexpr std::uint8_t kFdFlagEsi = 0x2;
constexpr std::int64_t kNsPerS = 1'000'000'000;
constexpr std::int64_t kNsPerUs = 1'000;
constexpr std::int64_t kMaxSeconds = (std::numeric_limits<std::int64_t>::max() - kNsPerS) / kNsPerS;

// ---- formatting ----
// Every piece is written into a fixed char buffer and appended to the line once: a log line is
// formatted per frame in the lockstep loop, and per-character string appends cost several times
// the digits themselves.

// The longest frame text: an 8-digit id, "##", the flags nibble and 64 data bytes.
constexpr std::size_t kMaxFrameChars = 8 + 2 + 1 + 2 * 64;
// "(" + up to 19 digits of seconds + "." + 6 digits + ")".
constexpr std::size_t kMaxTimestampChars = 1 + 19 + 1 + 6 + 1;

char* WriteHex(std::uint32_t value, int digits, char* out) {
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) {
    *out++ = kHexDigits[(value >> shift) & 0xF];
  }
  return out;
}

// `value` in decimal, left-padded with zeros to at least `min_digits`.
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
  HILRIG_CHECK(time_ns >= 0, "candump timestamps cannot be negative");
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
  const Result<void> valid = ValidateFrame(frame.frame);
  HILRIG_CHECK(valid.ok(), "cannot log an invalid frame: " + valid.error().message);
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

std::string FormatCandumpLine(const TimedCanFrame& frame, std::string_view interface_name) {
  std::string line;
  AppendCandumpLine(frame, interface_name, line);
  return line;
}

Result<std::pair<TimedCanFrame, std::string>> ParseCandumpLine(std::string_view line) {
  while (!line.empty() && IsSpace(line.back())) line.remove_suffix(1);
  auto parsed = ParseFields(line);
  if (!parsed) {
    return MakeError("bad candump line '" + std::string(line) + "': " + parsed.error().message);
  }
  return parsed;
}

CandumpLogWriter::CandumpLogWriter(std::ostream& out, std::string interface_name,
                                   DirectionMark mark)
    : out_(out), interface_name_(std::move(interface_name)), mark_(mark) {}

void CandumpLogWriter::Write(const TimedCanFrame& frame) {
  line_.clear();
  AppendCandumpLine(frame, interface_name_, line_, mark_);
  line_.push_back('\n');
  out_.write(line_.data(), static_cast<std::streamsize>(line_.size()));
  ++frames_written_;
}

std::uint64_t CandumpLogWriter::frames_written() const { return frames_written_; }

}  // namespace hilrig::rig
