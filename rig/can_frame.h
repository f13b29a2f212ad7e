// CanFrame is the one in-memory representation of a CAN 2.0 or CAN FD frame that every bus
// backend, log and device emulator exchanges. It mirrors Linux's canfd_frame closely enough that
// the SocketCAN backend and the candump log translate field by field, but keeps the flag bits out
// of the id so that ids compare as plain numbers. The timing helpers give the worst-case time a
// frame occupies the wire, which the emulated bus uses to serialize traffic realistically.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <span>

#include "rig/result.h"

namespace hilrig::rig {

inline constexpr std::uint32_t kMaxStandardId = 0x7FF;
inline constexpr std::uint32_t kMaxExtendedId = 0x1FFFFFFF;

struct CanFrame {
  static constexpr std::size_t kMaxClassicPayload = 8;
  static constexpr std::size_t kMaxFdPayload = 64;

  std::uint32_t id = 0;                // 11- or 29-bit identifier without flag bits
  bool extended = false;               // 29-bit id (EFF)
  bool remote = false;                 // RTR
  bool error = false;                  // error frame (id holds the CAN_ERR_* class bits like Linux)
  bool fd = false;                     // CAN FD frame
  bool bitrate_switch = false;         // FD BRS
  bool error_state_indicator = false;  // FD ESI
  std::uint8_t length = 0;             // payload bytes; for a remote frame the requested length
  std::array<std::uint8_t, kMaxFdPayload> data{};

  // Empty for remote frames: they request data but carry none on the wire.
  std::span<const std::uint8_t> payload() const;

  // The factories abort on arguments that cannot form the named kind of frame; use
  // ValidateFrame for frames assembled from untrusted input.
  static CanFrame Classic(std::uint32_t id, std::span<const std::uint8_t> payload);
  static CanFrame ClassicExtended(std::uint32_t id, std::span<const std::uint8_t> payload);
  static CanFrame Fd(std::uint32_t id, std::span<const std::uint8_t> payload, bool bitrate_switch);
  static CanFrame FdExtended(std::uint32_t id, std::span<const std::uint8_t> payload,
                             bool bitrate_switch);
  static CanFrame Remote(std::uint32_t id, std::uint8_t length, bool extended);
  // Linux-style error frame: `class_bits` are the CAN_ERR_* class flags, data is always 8 bytes.
  static CanFrame ErrorFrame(std::uint32_t class_bits,
                             const std::array<std::uint8_t, kMaxClassicPayload>& data);

  friend bool operator==(const CanFrame& a, const CanFrame& b);
};

bool IsValidFdLength(std::size_t length);  // 0..8, 12, 16, 20, 24, 32, 48, 64
// Rounds up to the next valid FD length like Linux's can_fd_len2dlc; length must be <= 64.
std::uint8_t DlcFromLength(std::size_t length);
// Classic frames cap DLC 9..15 at 8 bytes, as the CAN 2.0 standard says; dlc must be <= 15.
std::size_t LengthFromDlc(std::uint8_t dlc, bool fd);

// Checks what the wire and Linux can represent: id range per extended flag, length per fd flag,
// no remote FD frames, BRS/ESI only on FD frames, error frames classic and without EFF/RTR.
Result<void> ValidateFrame(const CanFrame& frame);
// The same test without the message, for paths that see every frame (bus, log writer) and only
// need the reason when the answer is no: it builds no Result and no string. Inline, as it is
// called for every frame sent and logged.
inline bool IsValidFrame(const CanFrame& frame) {
  if (frame.length > CanFrame::kMaxFdPayload) return false;
  if (frame.error) {
    return !frame.extended && !frame.remote && !frame.fd && frame.id <= kMaxExtendedId &&
           frame.length <= CanFrame::kMaxClassicPayload;
  }
  if (frame.id > (frame.extended ? kMaxExtendedId : kMaxStandardId)) return false;
  if (frame.fd) return !frame.remote && IsValidFdLength(frame.length);
  return !frame.bitrate_switch && !frame.error_state_indicator &&
         frame.length <= CanFrame::kMaxClassicPayload;
}

// Bits a frame occupies on the wire, with worst-case stuffing, split by the bitrate they run at.
// Classic frames (and FD frames without BRS) are all nominal. FD frames with BRS count SOF..BRS
// and ACK..intermission as nominal and ESI..CRC delimiter as data. Error frames count as an active
// error flag with worst-case superposition (12) + delimiter (8) + intermission (3).
struct FrameBitCount {
  std::int64_t nominal_bits = 0;
  std::int64_t data_bits = 0;
};
FrameBitCount CountFrameBits(const CanFrame& frame);

// Worst-case time on the wire including intermission, so back-to-back frames can be laid end to
// end. Each phase is rounded up to whole nanoseconds.
std::int64_t FrameDurationNs(const CanFrame& frame, std::int64_t nominal_bitrate_bps,
                             std::int64_t data_bitrate_bps);

// Readable one-line form for diagnostics and test names, e.g. "123#DEADBEEF [fd brs]".
std::ostream& operator<<(std::ostream& out, const CanFrame& frame);

struct TimedCanFrame {
  CanFrame frame;
  std::int64_t time_ns = 0;
  bool tx_echo = false;  // the receiving endpoint's own frame coming back (CAN_RAW_RECV_OWN_MSGS)

  friend bool operator==(const TimedCanFrame&, const TimedCanFrame&) = default;
};

}  // namespace hilrig::rig
