#include "rig/can_frame.h"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>

namespace hilrig::rig {
namespace {

constexpr std::array<std::uint8_t, 16> kFdLengthByDlc = {0, 1,  2,  3,  4,  5,  6,  7,
                                                         8, 12, 16, 20, 24, 32, 48, 64};

// Shared by the data-frame factories so the id/length invariants live in one place.
CanFrame MakeDataFrame(std::uint32_t id, bool extended, bool fd,
                       std::span<const std::uint8_t> payload) {
  HILRIG_CHECK(id <= (extended ? kMaxExtendedId : kMaxStandardId), "CAN id out of range");
  HILRIG_CHECK(
      fd ? IsValidFdLength(payload.size()) : payload.size() <= CanFrame::kMaxClassicPayload,
      "payload length not representable in this frame kind");
  CanFrame frame;
  frame.id = id;
  frame.extended = extended;
  frame.fd = fd;
  frame.length = static_cast<std::uint8_t>(payload.size());
  std::copy(payload.begin(), payload.end(), frame.data.begin());
  return frame;
}

// Worst case: the first stuff bit after 5 equal bits, then one after every 4 more, because the
// stuff bit itself starts the next run.
std::int64_t WorstCaseStuffBits(std::int64_t stuffable_bits) {
  return stuffable_bits > 0 ? (stuffable_bits - 1) / 4 : 0;
}

FrameBitCount CountClassicBits(const CanFrame& frame) {
  // SOF, id, RTR, IDE, r0, DLC | SOF, base id, SRR, IDE, ext id, RTR, r1, r0, DLC.
  const std::int64_t header = frame.extended ? 39 : 19;
  const std::int64_t data = frame.remote ? 0 : 8 * std::int64_t{frame.length};
  const std::int64_t crc = 15;
  const std::int64_t stuffable = header + data + crc;
  // CRC delimiter, ACK slot, ACK delimiter, EOF (7), intermission (3).
  const std::int64_t tail = 13;
  return {stuffable + WorstCaseStuffBits(stuffable) + tail, 0};
}

FrameBitCount CountFdBits(const CanFrame& frame) {
  // SOF, id, RRS, IDE, FDF, res, BRS | SOF, base id, SRR, IDE, ext id, RRS, FDF, res, BRS.
  const std::int64_t arbitration = frame.extended ? 36 : 17;
  const std::int64_t control_and_data = 1 + 4 + 8 * std::int64_t{frame.length};  // ESI, DLC, data
  const std::int64_t arbitration_stuff = WorstCaseStuffBits(arbitration);
  const std::int64_t data_stuff =
      WorstCaseStuffBits(arbitration + control_and_data) - arbitration_stuff;
  // Stuff count (4) + CRC-17/21 + fixed stuff bits (6/7) + CRC delimiter.
  const std::int64_t crc_field = frame.length <= 16 ? 4 + 17 + 6 + 1 : 4 + 21 + 7 + 1;
  // ACK slot, ACK delimiter, EOF (7), intermission (3).
  const std::int64_t tail = 12;
  const std::int64_t nominal = arbitration + arbitration_stuff + tail;
  const std::int64_t data = control_and_data + data_stuff + crc_field;
  if (frame.bitrate_switch) return {nominal, data};
  return {nominal + data, 0};
}

std::int64_t BitsToNs(std::int64_t bits, std::int64_t bitrate_bps) {
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  return (bits * kNsPerS + bitrate_bps - 1) / bitrate_bps;
}

std::string HexId(std::uint32_t id) {
  char text[16];
  std::snprintf(text, sizeof(text), "0x%X", static_cast<unsigned>(id));
  return text;
}

Result<void> ValidateErrorFrame(const CanFrame& frame) {
  if (frame.extended || frame.remote || frame.fd) {
    return MakeError("error frame must not carry extended, remote or FD flags");
  }
  if (frame.id > kMaxExtendedId) return MakeError("error frame class bits exceed 29 bits");
  if (frame.length > CanFrame::kMaxClassicPayload) {
    return MakeError("error frame longer than 8 bytes");
  }
  return {};
}

}  // namespace

std::span<const std::uint8_t> CanFrame::payload() const {
  HILRIG_CHECK(length <= kMaxFdPayload, "CanFrame length exceeds 64");
  return {data.data(), remote ? std::size_t{0} : std::size_t{length}};
}

CanFrame CanFrame::Classic(std::uint32_t id, std::span<const std::uint8_t> payload) {
  return MakeDataFrame(id, /*extended=*/false, /*fd=*/false, payload);
}

CanFrame CanFrame::ClassicExtended(std::uint32_t id, std::span<const std::uint8_t> payload) {
  return MakeDataFrame(id, /*extended=*/true, /*fd=*/false, payload);
}

CanFrame CanFrame::Fd(std::uint32_t id, std::span<const std::uint8_t> payload,
                      bool bitrate_switch) {
  CanFrame frame = MakeDataFrame(id, /*extended=*/false, /*fd=*/true, payload);
  frame.bitrate_switch = bitrate_switch;
  return frame;
}

CanFrame CanFrame::FdExtended(std::uint32_t id, std::span<const std::uint8_t> payload,
                              bool bitrate_switch) {
  CanFrame frame = MakeDataFrame(id, /*extended=*/true, /*fd=*/true, payload);
  frame.bitrate_switch = bitrate_switch;
  return frame;
}

CanFrame CanFrame::Remote(std::uint32_t id, std::uint8_t length, bool extended) {
  HILRIG_CHECK(length <= kMaxClassicPayload, "remote frame length exceeds 8");
  CanFrame frame = MakeDataFrame(id, extended, /*fd=*/false, {});
  frame.remote = true;
  frame.length = length;
  return frame;
}

CanFrame CanFrame::ErrorFrame(std::uint32_t class_bits,
                              const std::array<std::uint8_t, kMaxClassicPayload>& data) {
  HILRIG_CHECK(class_bits <= kMaxExtendedId, "error class bits exceed 29 bits");
  CanFrame frame;
  frame.error = true;
  frame.id = class_bits;
  frame.length = kMaxClassicPayload;
  std::copy(data.begin(), data.end(), frame.data.begin());
  return frame;
}

bool operator==(const CanFrame& a, const CanFrame& b) {
  const auto pa = a.payload();
  const auto pb = b.payload();
  return a.id == b.id && a.extended == b.extended && a.remote == b.remote && a.error == b.error &&
         a.fd == b.fd && a.bitrate_switch == b.bitrate_switch &&
         a.error_state_indicator == b.error_state_indicator && a.length == b.length &&
         std::equal(pa.begin(), pa.end(), pb.begin(), pb.end());
}

bool IsValidFdLength(std::size_t length) {
  return std::find(kFdLengthByDlc.begin(), kFdLengthByDlc.end(), length) != kFdLengthByDlc.end();
}

std::uint8_t DlcFromLength(std::size_t length) {
  HILRIG_CHECK(length <= CanFrame::kMaxFdPayload, "CAN FD length exceeds 64");
  const auto it = std::lower_bound(kFdLengthByDlc.begin(), kFdLengthByDlc.end(), length);
  return static_cast<std::uint8_t>(it - kFdLengthByDlc.begin());
}

std::size_t LengthFromDlc(std::uint8_t dlc, bool fd) {
  HILRIG_CHECK(dlc <= 15, "DLC is a 4-bit field");
  return fd ? kFdLengthByDlc[dlc] : std::min<std::size_t>(dlc, CanFrame::kMaxClassicPayload);
}

Result<void> ValidateFrame(const CanFrame& frame) {
  if (IsValidFrame(frame)) return {};
  if (frame.length > CanFrame::kMaxFdPayload) return MakeError("length exceeds 64 bytes");
  if (frame.error) return ValidateErrorFrame(frame);
  if (frame.id > (frame.extended ? kMaxExtendedId : kMaxStandardId)) {
    return MakeError(std::string(frame.extended ? "extended" : "standard") + " id " +
                     HexId(frame.id) + " out of range");
  }
  if (frame.fd) {
    if (frame.remote) return MakeError("CAN FD has no remote frames");
    if (!IsValidFdLength(frame.length)) {
      return MakeError("length " + std::to_string(frame.length) + " is not a valid CAN FD length");
    }
    return {};
  }
  if (frame.bitrate_switch || frame.error_state_indicator) {
    return MakeError("BRS/ESI flags are only valid on CAN FD frames");
  }
  if (frame.length > CanFrame::kMaxClassicPayload) {
    return MakeError("classic frame length " + std::to_string(frame.length) + " exceeds 8");
  }
  return {};
}

FrameBitCount CountFrameBits(const CanFrame& frame) {
  if (frame.error) return {12 + 8 + 3, 0};
  return frame.fd ? CountFdBits(frame) : CountClassicBits(frame);
}

std::int64_t FrameDurationNs(const CanFrame& frame, std::int64_t nominal_bitrate_bps,
                             std::int64_t data_bitrate_bps) {
  HILRIG_CHECK(nominal_bitrate_bps > 0 && data_bitrate_bps > 0, "bitrates must be positive");
  const FrameBitCount bits = CountFrameBits(frame);
  return BitsToNs(bits.nominal_bits, nominal_bitrate_bps) +
         BitsToNs(bits.data_bits, data_bitrate_bps);
}

std::ostream& operator<<(std::ostream& out, const CanFrame& frame) {
  char id[16];
  std::snprintf(id, sizeof(id), frame.extended || frame.error ? "%08X" : "%03X", frame.id);
  out << id << '#';
  if (frame.remote) out << 'R' << static_cast<int>(frame.length);
  for (std::uint8_t byte : frame.payload()) {
    char hex[3];
    std::snprintf(hex, sizeof(hex), "%02X", byte);
    out << hex;
  }
  if (frame.fd) out << (frame.bitrate_switch ? " [fd brs]" : " [fd]");
  if (frame.error) out << " [error]";
  return out;
}

}  // namespace hilrig::rig
