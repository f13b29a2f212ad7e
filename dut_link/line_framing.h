// Framing of the HIL link on a byte stream (a UART, USB CDC or a pseudo-terminal): each message is
// its payload followed by a CRC-16, COBS-encoded, and ended by a 0x00 byte. COBS leaves no 0x00
// inside a frame, so the delimiter alone marks every frame boundary: after garbage, a lost byte or
// a flipped one, the decoder is back in step at the next 0x00 and at most the frame it was in is
// lost. The CRC is CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor),
// little-endian after the payload: Hamming distance 4 up to 4093 bytes, so every 1-, 2- and 3-bit
// error in the decoded payload and CRC is caught, as is every burst up to 16 bits. A flipped COBS
// code byte moves the decoded zeros instead; it is caught as malformed COBS or by the CRC with the
// generic 1 - 2^-16 chance. A frame costs the payload + 2 + 1 + one code byte per 254 bytes at
// most. Portable like the rest of dut_link: fixed buffers, no allocation, no clock.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace hilrig::dut_link {

inline constexpr std::uint8_t kFrameDelimiter = 0x00;
inline constexpr std::size_t kFrameCrcBytes = 2;
// The largest LinkMessage a serial HIL link carries (the DutConfig of a six-pad scene is the
// largest, about 2 KB); the TCP link has the same limit.
inline constexpr std::size_t kMaxLineMessageBytes = 4096;

constexpr std::uint16_t Crc16CcittFalse(std::span<const std::uint8_t> bytes,
                                        std::uint16_t crc = 0xFFFF) {
  for (const std::uint8_t byte : bytes) {
    crc = std::uint16_t(crc ^ (std::uint16_t(byte) << 8));
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000) ? std::uint16_t((crc << 1) ^ 0x1021) : std::uint16_t(crc << 1);
    }
  }
  return crc;
}

// The most bytes a payload of `payload_bytes` takes on the line, delimiter included; reached when
// the payload and its CRC hold no 0x00.
constexpr std::size_t EncodedFrameBytes(std::size_t payload_bytes) {
  const std::size_t body = payload_bytes + kFrameCrcBytes;
  return body + body / 254 + 1 + 1;
}

// Writes the line form of `payload` into `out` and returns its size; 0 (nothing usable written)
// when `out` is too small.
constexpr std::size_t EncodeFrame(std::span<const std::uint8_t> payload,
                                  std::span<std::uint8_t> out) {
  if (out.size() < EncodedFrameBytes(payload.size())) return 0;
  const std::uint16_t crc = Crc16CcittFalse(payload);
  const std::array<std::uint8_t, kFrameCrcBytes> crc_bytes = {std::uint8_t(crc & 0xFF),
                                                              std::uint8_t(crc >> 8)};
  std::size_t code_at = 0;  // where the current block's code byte goes
  std::size_t written = 1;
  std::uint8_t code = 1;  // 1 + bytes in the current block
  const auto put = [&](std::uint8_t byte) {
    if (byte != 0) {
      out[written++] = byte;
      ++code;
    }
    if (byte == 0 || code == 0xFF) {
      out[code_at] = code;
      code_at = written++;
      code = 1;
    }
  };
  for (const std::uint8_t byte : payload) put(byte);
  for (const std::uint8_t byte : crc_bytes) put(byte);
  out[code_at] = code;
  out[written++] = kFrameDelimiter;
  return written;
}

struct FrameDecoderCounters {
  std::uint32_t frames = 0;         // frames delivered
  std::uint32_t bad_checksums = 0;  // well-formed COBS whose CRC did not match
  std::uint32_t malformed = 0;      // not valid COBS, or shorter than the CRC
  std::uint32_t oversize = 0;       // longer than the decoder's buffer; skipped to the delimiter
};

// Streaming decoder: one byte in, at most one payload out. The payload view stays valid until the
// next Feed. Empty frames (two delimiters in a row) are idle line, not errors: a sender may lead
// with a delimiter to flush whatever a receiver has half assembled.
template <std::size_t kMaxPayloadBytes>
class FrameDecoder {
 public:
  constexpr std::optional<std::span<const std::uint8_t>> Feed(std::uint8_t byte) {
    if (byte != kFrameDelimiter) {
      if (overflowed_) return std::nullopt;
      if (pending_len_ == pending_.size()) {
        overflowed_ = true;
        ++counters_.oversize;
        return std::nullopt;
      }
      pending_[pending_len_++] = byte;
      return std::nullopt;
    }
    const std::size_t encoded = pending_len_;
    const bool overflowed = overflowed_;
    pending_len_ = 0;
    overflowed_ = false;
    if (overflowed || encoded == 0) return std::nullopt;
    return Decode(encoded);
  }

  constexpr const FrameDecoderCounters& counters() const { return counters_; }

 private:
  // Decodes pending_[0, encoded) in place (the decoded form is never longer) and checks the CRC.
  constexpr std::optional<std::span<const std::uint8_t>> Decode(std::size_t encoded) {
    std::size_t read = 0;
    std::size_t decoded = 0;
    while (read < encoded) {
      const std::uint8_t code = pending_[read++];
      if (read - 1 + code > encoded) {
        ++counters_.malformed;
        return std::nullopt;
      }
      for (std::uint8_t i = 1; i < code; ++i) pending_[decoded++] = pending_[read++];
      if (code != 0xFF && read < encoded) pending_[decoded++] = 0;
    }
    if (decoded < kFrameCrcBytes) {
      ++counters_.malformed;
      return std::nullopt;
    }
    const std::size_t payload_bytes = decoded - kFrameCrcBytes;
    const std::span<const std::uint8_t> payload(pending_.data(), payload_bytes);
    const auto received_crc =
        std::uint16_t(pending_[payload_bytes] | (pending_[payload_bytes + 1] << 8));
    if (Crc16CcittFalse(payload) != received_crc) {
      ++counters_.bad_checksums;
      return std::nullopt;
    }
    ++counters_.frames;
    return payload;
  }

  // The encoded frame without its delimiter: payload, CRC and the COBS code bytes.
  std::array<std::uint8_t, EncodedFrameBytes(kMaxPayloadBytes) - 1> pending_{};
  std::size_t pending_len_ = 0;
  bool overflowed_ = false;
  FrameDecoderCounters counters_;
};

}  // namespace hilrig::dut_link
