// MAVLink v2 framing on bytes only: the CRC-16/MCRF4XX checksum MAVLink uses, a frame encoder that
// applies the v2 payload zero-trim rule, and a stream parser that takes bytes in whatever chunks a
// transport delivers, resynchronises after garbage, drops what it cannot check (unknown message
// ids, impossible lengths, unknown incompatibility flags, MAVLink v1 frames) and counts each kind
// of drop. Message layouts live in host/mavlink/mavlink_messages.h; the parser learns each
// message's CRC_EXTRA and full payload length through a lookup function, so this layer knows no
// message. Nothing here allocates or throws; the parser's storage is one fixed buffer.
//
// Wire layout of a v2 frame (all multi-byte fields little-endian):
//   0xFD len incompat compat seq sysid compid msgid[3] payload[len] crc[2] (signature[13])
// An unsigned frame is at most 267 bytes; a signed one (incompat bit 0x01) at most 280, the
// figure MAVLink quotes as its maximum packet length.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace hilrig::mavlink {

inline constexpr std::uint8_t kStartV2 = 0xFD;
inline constexpr std::uint8_t kStartV1 = 0xFE;
// Start byte through the 24-bit message id.
inline constexpr std::size_t kHeaderBytes = 10;
inline constexpr std::size_t kChecksumBytes = 2;
// Link id (1), timestamp (6) and signature (6), after the checksum of a signed frame.
inline constexpr std::size_t kSignatureBytes = 13;
inline constexpr std::size_t kMaxPayloadBytes = 255;
// The largest frame EncodeFrame writes (it never signs).
inline constexpr std::size_t kMaxFrameBytes = kHeaderBytes + kMaxPayloadBytes + kChecksumBytes;
static_assert(kMaxFrameBytes == 267);
inline constexpr std::size_t kMaxSignedFrameBytes = kMaxFrameBytes + kSignatureBytes;
static_assert(kMaxSignedFrameBytes == 280);
// v1: 0xFE len seq sysid compid msgid, payload, crc[2].
inline constexpr std::size_t kV1HeaderBytes = 6;
inline constexpr std::uint8_t kIncompatSigned = 0x01;
inline constexpr std::uint32_t kMaxMessageId = 0xFFFFFF;

// CRC-16/MCRF4XX ("X.25" in MAVLink's sources): reflected polynomial 0x8408, no final xor.
inline constexpr std::uint16_t kCrcInit = 0xFFFF;

// Folds one byte into `crc`. Cannot fail; does not allocate.
constexpr std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc) {
  std::uint8_t tmp = static_cast<std::uint8_t>(byte ^ static_cast<std::uint8_t>(crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ static_cast<std::uint8_t>(tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

// Folds `bytes` into `crc`. Cannot fail; O(bytes); does not allocate.
constexpr std::uint16_t CrcAccumulate(std::span<const std::uint8_t> bytes, std::uint16_t crc) {
  for (const std::uint8_t byte : bytes) crc = CrcAccumulate(byte, crc);
  return crc;
}

// Folds the characters of `text` into `crc` (used for CRC_EXTRA). Cannot fail; O(text); does not
// allocate.
constexpr std::uint16_t CrcAccumulate(std::string_view text, std::uint16_t crc) {
  for (const char c : text) crc = CrcAccumulate(static_cast<std::uint8_t>(c), crc);
  return crc;
}

// One v2 frame without its signature. payload_length counts the payload bytes on the wire: a
// parsed frame has the (possibly trimmed) wire length and zeros in every byte after it; a frame
// given to EncodeFrame has the message's full length, and the encoder trims.
struct Frame {
  std::uint8_t incompat_flags = 0;
  std::uint8_t compat_flags = 0;
  std::uint8_t sequence = 0;
  std::uint8_t system_id = 0;
  std::uint8_t component_id = 0;
  std::uint32_t message_id = 0;
  std::uint8_t payload_length = 0;
  std::array<std::uint8_t, kMaxPayloadBytes> payload{};

  bool operator==(const Frame&) const = default;
};

// The length of `payload` once its trailing zero bytes are dropped, never less than 1 (the v2 rule
// keeps the first byte of an all-zero payload). Cannot fail; O(payload); does not allocate.
std::size_t TrimmedPayloadLength(std::span<const std::uint8_t> payload);

// Writes `frame` to `out` with its payload trimmed and returns the bytes written (at most
// kMaxFrameBytes). Fails, returning 0 and leaving `out` unspecified, when `out` is too small, the
// message id needs more than 24 bits, or any incompat flag is set (this encoder does not sign).
// O(payload_length); does not allocate.
std::size_t EncodeFrame(const Frame& frame, std::uint8_t crc_extra, std::span<std::uint8_t> out);

// The total size of the v1 or v2 frame that starts at bytes[0], signature included, once its
// header shows it: nullopt when bytes[0] is no start byte or too few header bytes are there (v2
// needs 3, v1 needs 2). Cannot fail otherwise; does not allocate.
std::optional<std::size_t> FrameSizeFromHeader(std::span<const std::uint8_t> bytes);

// What the parser must know of a message to accept it.
struct WireInfo {
  std::uint8_t crc_extra = 0;
  // With extensions; longer wire payloads are rejected, shorter ones zero-extended.
  std::uint8_t full_payload_bytes = 0;
};

// Tells the parser about a message id; nullopt for ids it cannot check.
using WireInfoLookup = std::optional<WireInfo> (*)(std::uint32_t message_id);

// What the parser did with the bytes it was given. Each counted event consumes at least one byte,
// so the counters other than signed_frames add up to at most the bytes pushed.
struct ParserCounters {
  std::uint64_t frames_ok = 0;            // delivered by Next(), signed ones included
  std::uint64_t bytes_skipped = 0;        // dropped while looking for a start byte
  std::uint64_t crc_failures = 0;         // a checksum mismatch; the scan restarts one byte later
  std::uint64_t unknown_message_ids = 0;  // no CRC_EXTRA to check the frame with
  std::uint64_t bad_lengths = 0;          // payload longer than the message's full length
  std::uint64_t unsupported_incompat_flags = 0;  // an incompat bit other than "signed"
  std::uint64_t signed_frames = 0;      // delivered frames that carried a (skipped) signature
  std::uint64_t v1_frames_skipped = 0;  // MAVLink v1 frames passed over whole, undecoded
  std::uint64_t truncated_frames = 0;   // a frame still incomplete when Finish() was called

  bool operator==(const ParserCounters&) const = default;
};

// Splits a byte stream into checked v2 frames. Bytes go in with Push() (or Feed()), frames come
// out of Next(). A rejected candidate costs only its start byte: the scan resumes one byte after
// it, so a real frame hidden inside garbage or inside a corrupt frame is still found. A v1 frame
// is passed over whole; when the lookup knows its message id its checksum is checked first and a
// mismatch makes its start byte a skipped byte instead. Signatures are skipped, not verified.
//
// Threading: one parser is used from one thread at a time.
class FrameParser {
 public:
  // Two maximal signed frames, so a partial frame never blocks Push.
  static constexpr std::size_t kBufferBytes = 2 * kMaxSignedFrameBytes;

  // `lookup` must not be null. Cannot fail; does not allocate.
  explicit FrameParser(WireInfoLookup lookup);

  // Copies as many leading bytes of `bytes` as the buffer has room for and returns how many; call
  // Next() until it returns nullopt before pushing the rest (after that at least
  // kBufferBytes - kMaxSignedFrameBytes + 1 bytes fit). Starts a new stream after Finish().
  // Cannot fail; O(bytes + kMaxSignedFrameBytes); does not allocate.
  std::size_t Push(std::span<const std::uint8_t> bytes);

  // The next checked frame in the buffered bytes, or nullopt when the buffer holds at most an
  // incomplete frame. Cannot fail; O(buffered bytes x frame size) at worst (every start byte of a
  // corrupt stream may be checked); does not allocate.
  std::optional<Frame> Next();

  // Declares the end of the stream: from now on Next() gives up on an incomplete frame (counted
  // in truncated_frames) and scans on from its next byte instead of waiting. Cannot fail; does not
  // allocate.
  void Finish();

  // Pushes all of `bytes`, calling on_frame(const Frame&) for each frame in order. Cannot fail;
  // O(bytes) plus Next()'s cost; does not allocate (beyond what on_frame does).
  template <typename OnFrame>
  void Feed(std::span<const std::uint8_t> bytes, OnFrame&& on_frame) {
    for (;;) {
      bytes = bytes.subspan(Push(bytes));
      while (std::optional<Frame> frame = Next()) on_frame(*frame);
      if (bytes.empty()) return;
    }
  }

  // Drops buffered bytes (uncounted) and the end-of-stream mark; keeps the counters. Cannot fail;
  // does not allocate.
  void Reset();

  // Cannot fail; does not allocate.
  const ParserCounters& counters() const { return counters_; }
  // Bytes pushed and not yet consumed. Cannot fail; does not allocate.
  std::size_t buffered_bytes() const { return end_ - begin_; }

 private:
  WireInfoLookup lookup_;
  std::array<std::uint8_t, kBufferBytes> buffer_{};
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool input_ended_ = false;
  ParserCounters counters_;
};

}  // namespace hilrig::mavlink
