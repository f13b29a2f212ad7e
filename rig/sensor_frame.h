// PROVISIONAL codec for one magnetometer sample per classic CAN frame, so emulators and the DUT
// can exchange tactile data before the real tactile protocol exists. A later issue replaces this
// with the layout defined in proto/ (with a DBC); keep every knowledge of the layout in this file.
//
// Layout: id = kSensorSampleBaseId + node_id, 8 bytes: x, y, z as little-endian int16 raw codes,
// then sequence, then status.
#pragma once

#include <cstdint>

#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

inline constexpr std::uint32_t kSensorSampleBaseId = 0x100;  // id = base + node_id
inline constexpr std::uint8_t kFirstTactileNodeId = 1;
inline constexpr std::uint8_t kLastTactileNodeId = 6;
inline constexpr std::uint8_t kReferenceNodeId = 7;

// Status bits. Unknown bits are passed through so newer node firmware does not break decoding.
inline constexpr std::uint8_t kSensorStatusSaturated = 1u << 0;
inline constexpr std::uint8_t kSensorStatusConversionError = 1u << 1;
inline constexpr std::uint8_t kSensorStatusStale = 1u << 2;

struct MagneticSample {
  std::uint8_t node_id = 0;  // 1..6 tactile, 7 reference
  std::int16_t x_code = 0;
  std::int16_t y_code = 0;
  std::int16_t z_code = 0;
  std::uint8_t sequence = 0;  // wraps; lets the receiver detect lost frames
  std::uint8_t status = 0;

  friend bool operator==(const MagneticSample&, const MagneticSample&) = default;
};

// Aborts on a node id outside 1..7: only rig code builds samples.
CanFrame EncodeMagneticSample(const MagneticSample& sample);
// Rejects frames that are not sample frames (id range, length, extended/remote/FD/error flags).
Result<MagneticSample> DecodeMagneticSample(const CanFrame& frame);

}  // namespace hilrig::rig
