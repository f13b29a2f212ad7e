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

void AppendHex(std::uint32_t value, int digits, std::string& out) {
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) {
    out.push_back(kHexDigits[(value >> shift) & 0xF]);
  }
}

void AppendDecimal(std::int64_t value, std::size_t min_digits, std::string& out) {
  std::array<char, 24> digits;
  const auto end = std::to_chars(digits.data(), digits.data() + digits.size(), value).ptr;
  const auto count = static_cast<std::size_t>(end - digits.data());
  if (count < min_digits) out.append(min_digits - count, '0');
  out.append(digits.data(), count);
}

void AppendTimestamp(std::int64_t time_ns, std::string& out) {
  HILRIG_CHECK(time_ns >= 0, "candump timestamps cannot be negative");
  out.push_back('(');
  AppendDecimal(time_ns / kNsPerS, 10, out);
  out.push_back('.');
  AppendDecimal((time_ns % kNsPerS) / kNsPerUs, 6, out);
  out.push_back(')');
}

void AppendId(const CanFrame& frame, std::string& out) {
  if (frame.error) {
    AppendHex(frame.id | kCanErrFlag, 8, out);
  } else if (frame.extended) {
    AppendHex(frame.id, 8, out);
  } else {
    AppendHex(frame.id, 3, out);
  }
}

void AppendFrame(const CanFrame& frame, std::string& out) {
  AppendId(frame, out);
  out.push_back('#');
  if (frame.remote) {
    out.push_back('R');
    if (frame.length > 0) out.push_back(kHexDigits[frame.length]);
    return;
  }
  if (frame.fd) {
    out.push_back('#');
    out.push_back(kHexDigits[(frame.bitrate_switch ? kFdFlagBrs : 0) |
                             (frame.error_state_indicator ? kFdFlagEsi : 0)]);
  }
  for (const std::uint8_t byte : frame.payload()) {
    out.push_back(kHexDigits[byte >> 4]);
    out.push_back(kHexDigits[byte & 0xF]);
  }
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
  AppendTimestamp(frame.time_ns, out);
  out.push_back(' ');
  out.append(interface_name);
  out.push_back(' ');
  AppendFrame(frame.frame, out);
  if (mark == DirectionMark::kRxTx) out.append(frame.tx_echo ? " T" : " R");
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
