#include "host/mavlink/tlog.h"

#include <array>
#include <optional>

namespace hilrig::mavlink {
namespace {

std::uint64_t ReadBigEndian64(std::span<const std::uint8_t> bytes) {
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < kTlogTimestampBytes; ++i) value = (value << 8) | bytes[i];
  return value;
}

enum class RecordCheck { kFrame, kV1Frame, kRejected };

// Whether `frame_bytes` (exactly one frame's worth, starting with a start byte) hold one checked
// frame and nothing else.
RecordCheck CheckRecord(std::span<const std::uint8_t> frame_bytes, WireInfoLookup lookup,
                        Frame& frame) {
  FrameParser parser(lookup);
  parser.Push(frame_bytes);
  parser.Finish();
  const std::optional<Frame> parsed = parser.Next();
  const bool drained = !parser.Next().has_value() && parser.buffered_bytes() == 0;
  ParserCounters clean_frame;
  clean_frame.frames_ok = 1;
  if (parsed && (parsed->incompat_flags & kIncompatSigned) != 0) clean_frame.signed_frames = 1;
  if (parsed && drained && parser.counters() == clean_frame) {
    frame = *parsed;
    return RecordCheck::kFrame;
  }
  ParserCounters clean_v1;
  clean_v1.v1_frames_skipped = 1;
  if (!parsed && parser.counters() == clean_v1) return RecordCheck::kV1Frame;
  return RecordCheck::kRejected;
}

}  // namespace

TlogWriter::TlogWriter(std::ostream& out) : out_(out) {}

bool TlogWriter::Write(std::uint64_t time_us, std::span<const std::uint8_t> frame) {
  if (frame.empty() || frame.size() > kMaxSignedFrameBytes) return false;
  std::array<char, kTlogTimestampBytes> stamp;
  for (std::size_t i = 0; i < kTlogTimestampBytes; ++i) {
    stamp[i] = static_cast<char>(time_us >> (8 * (kTlogTimestampBytes - 1 - i)));
  }
  out_.write(stamp.data(), static_cast<std::streamsize>(stamp.size()));
  out_.write(reinterpret_cast<const char*>(frame.data()),
             static_cast<std::streamsize>(frame.size()));
  return out_.good();
}

TlogContents ReadTlog(std::span<const std::uint8_t> bytes, WireInfoLookup lookup) {
  TlogContents contents;
  std::size_t pos = 0;
  while (bytes.size() - pos > kTlogTimestampBytes) {
    const std::span<const std::uint8_t> rest = bytes.subspan(pos + kTlogTimestampBytes);
    const std::optional<std::size_t> size = FrameSizeFromHeader(rest);
    if (size && *size <= rest.size()) {
      Frame frame;
      switch (CheckRecord(rest.first(*size), lookup, frame)) {
        case RecordCheck::kFrame:
          contents.records.push_back({ReadBigEndian64(bytes.subspan(pos)), frame});
          pos += kTlogTimestampBytes + *size;
          continue;
        case RecordCheck::kV1Frame:
          ++contents.v1_records_skipped;
          pos += kTlogTimestampBytes + *size;
          continue;
        case RecordCheck::kRejected:
          break;
      }
    }
    ++contents.bytes_skipped;
    ++pos;
  }
  contents.bytes_skipped += bytes.size() - pos;
  return contents;
}

}  // namespace hilrig::mavlink
