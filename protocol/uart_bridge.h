// The UART bridge of the tactile bus: how a sensor node streams every CAN frame it sees over its
// UART to the flight controller (proto/TACTILE_PROTOCOL.md), and how the controller reads them
// back. Both ends include this one header: the node firmware (dut_fw/sensor_node.h), the DUT side
// of the HIL link (dut_link/serial_session.h) and the rig's side
// (host/linked_dut/serial_dut_link.cc).
//
// A frame: 0xAA 0x55 id_lo id_hi len data[len] crc8, with the CRC-8/ATM polynomial 0x07 (init 0, no
// reflection, no final xor -- CRC-8/SMBUS in the reveng catalogue; ITU I.432.1's HEC would also xor
// 0x55) over id_lo..data. A frame is 6..14 bytes. Hamming distance 4 up to 119 message bits covers
// every frame, so all 1-, 2- and 3-bit errors in id..crc are caught; an error in len moves where
// the CRC is looked for and slips through with the generic 1/256 chance.
//
// Portable: header-only, constexpr, no allocation; every function is O(frame bytes) and none fails
// other than by its return value.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace hilrig::tactile_bus {

// A classic CAN frame as the node's CAN peripheral sees it: 11-bit id, 0..8 data bytes.
struct NodeFrame {
  std::uint16_t id = 0;
  std::uint8_t len = 0;
  std::array<std::uint8_t, 8> data{};

  friend constexpr bool operator==(const NodeFrame&, const NodeFrame&) = default;
};

// The two bytes every bridge frame starts with, and the longest frame (8 data bytes).
inline constexpr std::uint8_t kUartSync0 = 0xAA;
inline constexpr std::uint8_t kUartSync1 = 0x55;
inline constexpr std::size_t kUartMaxFrameBytes = 2 + 2 + 1 + 8 + 1;

// CRC-8/ATM of `count` bytes, continuing from `crc`.
constexpr std::uint8_t Crc8Atm(const std::uint8_t* bytes, std::size_t count, std::uint8_t crc = 0) {
  for (std::size_t i = 0; i < count; ++i) {
    crc = std::uint8_t(crc ^ bytes[i]);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x80) ? std::uint8_t((crc << 1) ^ 0x07) : std::uint8_t(crc << 1);
    }
  }
  return crc;
}

// Writes the UART form of `frame` and returns its size; 0 (nothing written) for a frame no CAN
// 2.0 bus carries (id above 0x7FF or more than 8 bytes).
constexpr std::size_t EncodeUartFrame(const NodeFrame& frame,
                                      std::array<std::uint8_t, kUartMaxFrameBytes>& out) {
  if (frame.id > 0x7FF || frame.len > 8) return 0;
  out[0] = kUartSync0;
  out[1] = kUartSync1;
  out[2] = std::uint8_t(frame.id & 0xFF);
  out[3] = std::uint8_t(frame.id >> 8);
  out[4] = frame.len;
  for (std::size_t i = 0; i < frame.len; ++i) out[5 + i] = frame.data[i];
  out[5 + frame.len] = Crc8Atm(&out[2], 3 + std::size_t(frame.len));
  return 6 + std::size_t(frame.len);
}

struct UartDecoderCounters {
  std::uint32_t frames = 0;         // frames delivered
  std::uint32_t bad_checksums = 0;  // complete candidates whose CRC did not match
  std::uint32_t bad_lengths = 0;    // candidates with len > 8
  std::uint32_t bad_ids = 0;        // candidates with an id above 0x7FF
  std::uint32_t skipped_bytes = 0;  // bytes discarded while looking for a frame start
};

// Streaming decoder: one byte in, at most one frame out. It keeps the bytes of the candidate frame
// it is assembling; when a candidate fails (bad id, length or CRC) it resumes at the next 0xAA
// after the failed candidate's start, not after its end, so garbage that happens to look like a
// header can never swallow a real frame that follows it. Every failure is counted, none is fatal.
class UartDecoder {
 public:
  constexpr std::optional<NodeFrame> Feed(std::uint8_t byte) {
    pending_[pending_len_++] = byte;
    while (pending_len_ > 0) {
      switch (Inspect()) {
        case Verdict::kNeedMore:
          return std::nullopt;
        case Verdict::kComplete:
          return TakeFrame();
        case Verdict::kBadSync:
          break;
        case Verdict::kBadId:
          ++counters_.bad_ids;
          break;
        case Verdict::kBadLength:
          ++counters_.bad_lengths;
          break;
        case Verdict::kBadChecksum:
          ++counters_.bad_checksums;
          break;
      }
      DropToNextSync();
    }
    return std::nullopt;
  }

  constexpr const UartDecoderCounters& counters() const { return counters_; }

 private:
  enum class Verdict { kNeedMore, kComplete, kBadSync, kBadId, kBadLength, kBadChecksum };

  constexpr Verdict Inspect() const {
    if (pending_[0] != kUartSync0) return Verdict::kBadSync;
    if (pending_len_ < 2) return Verdict::kNeedMore;
    if (pending_[1] != kUartSync1) return Verdict::kBadSync;
    if (pending_len_ < 4) return Verdict::kNeedMore;
    if ((pending_[3] & 0xF8) != 0) return Verdict::kBadId;
    if (pending_len_ < 5) return Verdict::kNeedMore;
    if (pending_[4] > 8) return Verdict::kBadLength;
    const std::size_t total = 6 + std::size_t(pending_[4]);
    if (pending_len_ < total) return Verdict::kNeedMore;
    const std::uint8_t crc = Crc8Atm(&pending_[2], total - 3);
    return crc == pending_[total - 1] ? Verdict::kComplete : Verdict::kBadChecksum;
  }

  constexpr NodeFrame TakeFrame() {
    NodeFrame frame;
    frame.id = std::uint16_t(pending_[2] | (pending_[3] << 8));
    frame.len = pending_[4];
    for (std::size_t i = 0; i < frame.len; ++i) frame.data[i] = pending_[5 + i];
    pending_len_ = 0;
    ++counters_.frames;
    return frame;
  }

  // Discards the failed candidate's first byte and everything up to the next sync byte.
  constexpr void DropToNextSync() {
    std::size_t next = 1;
    while (next < pending_len_ && pending_[next] != kUartSync0) ++next;
    counters_.skipped_bytes += std::uint32_t(next);
    for (std::size_t i = next; i < pending_len_; ++i) pending_[i - next] = pending_[i];
    pending_len_ -= next;
  }

  std::array<std::uint8_t, kUartMaxFrameBytes> pending_{};
  std::size_t pending_len_ = 0;
  UartDecoderCounters counters_;
};

}  // namespace hilrig::tactile_bus
