// PROVISIONAL API for one magnetometer sample per classic CAN frame, kept so host code written
// against it keeps building while it migrates to rig/tactile_protocol.h. It is a thin forwarder:
// the layout lives only in the tactile protocol codec (see proto/TACTILE_PROTOCOL.md); this file
// merely re-expresses the result words as int16 the way the first host code expected them.
#pragma once

#include <cstdint>

#include "rig/can_frame.h"
#include "rig/result.h"
#include "rig/tactile_protocol.h"

namespace hilrig::rig {

inline constexpr std::uint32_t kSensorSampleBaseId = kTactileSampleBaseId;  // id = base + node_id

inline constexpr std::uint8_t kSensorStatusSaturated = kSampleStatusSaturated;
inline constexpr std::uint8_t kSensorStatusConversionError = kSampleStatusConversionError;
inline constexpr std::uint8_t kSensorStatusStale = kSampleStatusStale;

struct MagneticSample {
  std::uint8_t node_id = 0;  // 1..6 tactile, 7 reference
  std::int16_t x_code = 0;   // the chip's result words, bit for bit
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
