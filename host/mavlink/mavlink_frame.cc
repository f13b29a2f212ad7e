#include "host/mavlink/mavlink_frame.h"

#include <algorithm>
#include <cstring>

namespace hilrig::mavlink {
namespace {

// How the parser classifies the candidate under its scan position.
enum class ScanOutcome {
  kFrame,                     // a checked v2 frame
  kNeedMoreBytes,             // incomplete: wait, or count as truncated after Finish()
  kCrcFailure,                // checksum mismatch
  kUnknownMessageId,          // the lookup has no entry
  kBadLength,                 // longer than the message's full payload
  kUnsupportedIncompatFlags,  // incompat bits other than kIncompatSigned
  kV1Frame,                   // a v1 frame, skipped whole
  kV1Garbage,                 // a 0xFE whose v1 frame failed its check
};

struct Scan {
  ScanOutcome outcome = ScanOutcome::kNeedMoreBytes;
  std::size_t frame_bytes = 0;  // bytes to consume for kFrame and kV1Frame
};

std::uint16_t ReadLe16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

// A v1 frame is only passed over, so only its checksum is checked, and only when the lookup knows
// its (8-bit) id; an unknown id is trusted, its frame skipped by its length byte.
Scan ClassifyV1(std::span<const std::uint8_t> c, WireInfoLookup lookup) {
  if (c.size() < 2) return {};
  const std::size_t total = kV1HeaderBytes + c[1] + kChecksumBytes;
  if (c.size() < total) return {};
  if (const std::optional<WireInfo> info = lookup(c[5])) {
    std::uint16_t crc = CrcAccumulate(c.subspan(1, kV1HeaderBytes - 1 + c[1]), kCrcInit);
    crc = CrcAccumulate(info->crc_extra, crc);
    if (crc != ReadLe16(&c[kV1HeaderBytes + c[1]])) return {ScanOutcome::kV1Garbage, 0};
  }
  return {ScanOutcome::kV1Frame, total};
}

Scan ClassifyV2(std::span<const std::uint8_t> c, WireInfoLookup lookup, Frame& frame) {
  if (c.size() < kHeaderBytes) return {};
  const std::uint8_t length = c[1];
  const std::uint8_t incompat = c[2];
  if ((incompat & ~kIncompatSigned) != 0) return {ScanOutcome::kUnsupportedIncompatFlags, 0};
  const std::uint32_t id = c[7] | (c[8] << 8) | (static_cast<std::uint32_t>(c[9]) << 16);
  const std::optional<WireInfo> info = lookup(id);
  if (!info) return {ScanOutcome::kUnknownMessageId, 0};
  if (length > info->full_payload_bytes) return {ScanOutcome::kBadLength, 0};
  const bool is_signed = (incompat & kIncompatSigned) != 0;
  const std::size_t total =
      kHeaderBytes + length + kChecksumBytes + (is_signed ? kSignatureBytes : 0);
  if (c.size() < total) return {};
  std::uint16_t crc = CrcAccumulate(c.subspan(1, kHeaderBytes - 1 + length), kCrcInit);
  crc = CrcAccumulate(info->crc_extra, crc);
  if (crc != ReadLe16(&c[kHeaderBytes + length])) return {ScanOutcome::kCrcFailure, 0};
  frame.incompat_flags = incompat;
  frame.compat_flags = c[3];
  frame.sequence = c[4];
  frame.system_id = c[5];
  frame.component_id = c[6];
  frame.message_id = id;
  frame.payload_length = length;
  std::copy_n(&c[kHeaderBytes], length, frame.payload.begin());
  return {ScanOutcome::kFrame, total};
}

}  // namespace

std::size_t TrimmedPayloadLength(std::span<const std::uint8_t> payload) {
  std::size_t length = payload.size();
  while (length > 1 && payload[length - 1] == 0) --length;
  return std::max<std::size_t>(length, 1);
}

std::size_t EncodeFrame(const Frame& frame, std::uint8_t crc_extra, std::span<std::uint8_t> out) {
  if (frame.message_id > kMaxMessageId || frame.incompat_flags != 0) return 0;
  const std::span<const std::uint8_t> payload(frame.payload.data(), frame.payload_length);
  const std::size_t length = TrimmedPayloadLength(payload);
  const std::size_t total = kHeaderBytes + length + kChecksumBytes;
  if (out.size() < total) return 0;
  out[0] = kStartV2;
  out[1] = static_cast<std::uint8_t>(length);
  out[2] = frame.incompat_flags;
  out[3] = frame.compat_flags;
  out[4] = frame.sequence;
  out[5] = frame.system_id;
  out[6] = frame.component_id;
  out[7] = static_cast<std::uint8_t>(frame.message_id);
  out[8] = static_cast<std::uint8_t>(frame.message_id >> 8);
  out[9] = static_cast<std::uint8_t>(frame.message_id >> 16);
  // An empty payload goes out as the single zero byte the v2 rule keeps.
  out[kHeaderBytes] = 0;
  std::copy_n(payload.begin(), std::min(length, payload.size()), &out[kHeaderBytes]);
  std::uint16_t crc = CrcAccumulate(out.subspan(1, kHeaderBytes - 1 + length), kCrcInit);
  crc = CrcAccumulate(crc_extra, crc);
  out[kHeaderBytes + length] = static_cast<std::uint8_t>(crc);
  out[kHeaderBytes + length + 1] = static_cast<std::uint8_t>(crc >> 8);
  return total;
}

std::optional<std::size_t> FrameSizeFromHeader(std::span<const std::uint8_t> bytes) {
  if (bytes.size() >= 3 && bytes[0] == kStartV2) {
    const bool is_signed = (bytes[2] & kIncompatSigned) != 0;
    return kHeaderBytes + bytes[1] + kChecksumBytes + (is_signed ? kSignatureBytes : 0);
  }
  if (bytes.size() >= 2 && bytes[0] == kStartV1) {
    return kV1HeaderBytes + bytes[1] + kChecksumBytes;
  }
  return std::nullopt;
}

FrameParser::FrameParser(WireInfoLookup lookup) : lookup_(lookup) {}

std::size_t FrameParser::Push(std::span<const std::uint8_t> bytes) {
  if (!bytes.empty()) input_ended_ = false;
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  const std::size_t taken = std::min(bytes.size(), buffer_.size() - end_);
  std::copy_n(bytes.begin(), taken, buffer_.begin() + static_cast<std::ptrdiff_t>(end_));
  end_ += taken;
  return taken;
}

std::optional<Frame> FrameParser::Next() {
  for (;;) {
    while (begin_ < end_ && buffer_[begin_] != kStartV2 && buffer_[begin_] != kStartV1) {
      ++begin_;
      ++counters_.bytes_skipped;
    }
    if (begin_ == end_) {
      begin_ = end_ = 0;
      return std::nullopt;
    }
    const std::span<const std::uint8_t> candidate(buffer_.data() + begin_, end_ - begin_);
    Frame frame;
    const Scan scan = candidate[0] == kStartV2 ? ClassifyV2(candidate, lookup_, frame)
                                               : ClassifyV1(candidate, lookup_);
    switch (scan.outcome) {
      case ScanOutcome::kFrame:
        begin_ += scan.frame_bytes;
        ++counters_.frames_ok;
        if ((frame.incompat_flags & kIncompatSigned) != 0) ++counters_.signed_frames;
        return frame;
      case ScanOutcome::kNeedMoreBytes:
        if (!input_ended_) return std::nullopt;
        ++counters_.truncated_frames;
        ++begin_;
        break;
      case ScanOutcome::kCrcFailure:
        ++counters_.crc_failures;
        ++begin_;
        break;
      case ScanOutcome::kUnknownMessageId:
        ++counters_.unknown_message_ids;
        ++begin_;
        break;
      case ScanOutcome::kBadLength:
        ++counters_.bad_lengths;
        ++begin_;
        break;
      case ScanOutcome::kUnsupportedIncompatFlags:
        ++counters_.unsupported_incompat_flags;
        ++begin_;
        break;
      case ScanOutcome::kV1Frame:
        ++counters_.v1_frames_skipped;
        begin_ += scan.frame_bytes;
        break;
      case ScanOutcome::kV1Garbage:
        ++counters_.bytes_skipped;
        ++begin_;
        break;
    }
  }
}

void FrameParser::Finish() { input_ended_ = true; }

void FrameParser::Reset() {
  begin_ = end_ = 0;
  input_ended_ = false;
}

}  // namespace hilrig::mavlink
