// The tactile bus protocol: the three kinds of classic CAN frame that the seven Hall sensor nodes
// and the host exchange, and the one codec in rig/ that knows their byte layout. proto/tactile.dbc
// states the same layout for other tools (tests/rig/tactile_dbc_test.cc keeps the two in step) and
// proto/TACTILE_PROTOCOL.md explains it. dut_fw/sensor_node.h is the node side of the same
// protocol; both take the protocol's numbers from protocol/tactile_bus.h, and the cross-check test
// in tests/rig/tactile_protocol_test.cc decodes the node's frames with this codec. Multi-byte
// fields are little-endian. Decoders never abort on what arrives from a bus: every malformed frame
// comes back as an Error that names the problem.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <variant>

#include "protocol/tactile_bus.h"
#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// The protocol's numbers (ids, lengths, status bits, flags, rates) are protocol/tactile_bus.h's.
// A rate's code from its Hz (one of tactile_bus::kRateHzByCode), and back.
std::optional<std::uint8_t> TactileRateCodeFromHz(std::uint16_t rate_hz);
std::optional<std::uint16_t> TactileRateHzFromCode(std::uint8_t rate_code);

enum class TactileFrameKind : std::uint8_t {
  kSample,
  kStatus,
  kConfig,
  kUnknownId,      // a classic data frame whose 11-bit id is not a tactile id
  kNotClassicData  // extended, remote, CAN FD or error frame: never part of the protocol
};

// Classifies by frame flags and id alone (not by length), so a monitor can attribute a frame of
// the wrong length to its node before decoding rejects it.
TactileFrameKind Classify(const CanFrame& frame);
// The node a sample, status or config frame belongs to (0 = broadcast config); nullopt for the
// other kinds.
std::optional<std::uint8_t> TactileNodeOf(const CanFrame& frame);
// The same for a frame already classified: `kind` must be Classify(frame). A monitor that looks at
// every frame on the bus classifies it once and hands the kind on.
std::optional<std::uint8_t> TactileNodeOf(const CanFrame& frame, TactileFrameKind kind);

struct TactileSample {
  std::uint8_t node_id = 0;             // 1..7
  std::array<std::uint16_t, 3> code{};  // MLX90393 x, y, z result words as read from the chip
  std::uint8_t sequence = 0;            // +1 per sample frame, wraps at 256
  std::uint8_t status = 0;              // kSampleStatus* bits

  friend bool operator==(const TactileSample&, const TactileSample&) = default;
};

struct TactileStatus {
  std::uint8_t node_id = 0;              // 1..7
  std::int16_t temperature_centi_c = 0;  // chip temperature, 0.01 °C
  std::uint8_t flags = 0;                // kNodeFlag* bits
  std::uint8_t gain_sel = 0;             // MLX90393 GAIN_SEL in use, 0..7
  std::uint8_t resolution = 0;           // MLX90393 RES_XYZ in use, 0..3
  std::uint8_t rate_code = 0;            // index into tactile_bus::kRateHzByCode
  std::uint8_t rx_error_count = 0;       // frames the node rejected, saturating at 255
  std::uint8_t firmware_version = 0;     // major in the high nibble, minor in the low

  friend bool operator==(const TactileStatus&, const TactileStatus&) = default;
};

// The configuration commands (tactile_bus::kCommand*).
enum class TactileCommand : std::uint8_t {
  kSetRate = tactile_bus::kCommandSetRate,
  kSetGain = tactile_bus::kCommandSetGain,
  kSetResolution = tactile_bus::kCommandSetResolution,
  kZero = tactile_bus::kCommandZero,
  kReset = tactile_bus::kCommandReset,
};

struct TactileConfigCommand {
  std::uint8_t node_id = 0;  // 1..7, or tactile_bus::kBroadcastNodeId for all nodes
  TactileCommand command = TactileCommand::kZero;
  std::uint16_t rate_hz = 0;    // kSetRate only
  std::uint8_t gain_sel = 0;    // kSetGain only
  std::uint8_t resolution = 0;  // kSetResolution only

  friend bool operator==(const TactileConfigCommand&, const TactileConfigCommand&) = default;
};

using TactileMessage = std::variant<TactileSample, TactileStatus, TactileConfigCommand>;

// The encoders abort on a struct no valid frame can carry (node id, command argument out of
// range): only rig code builds them. Config frames go out with 8 bytes, unused ones reserved and 0,
// so that DBC tools (which expect the DBC's length) decode them; nodes accept 2..8.
CanFrame EncodeTactileSample(const TactileSample& sample);
CanFrame EncodeTactileStatus(const TactileStatus& status);
CanFrame EncodeTactileConfig(const TactileConfigCommand& command);

Result<TactileSample> DecodeTactileSample(const CanFrame& frame);
Result<TactileStatus> DecodeTactileStatus(const CanFrame& frame);
// Accepts 2..8 bytes: bytes past the command's arguments are reserved and ignored.
Result<TactileConfigCommand> DecodeTactileConfig(const CanFrame& frame);
// Dispatches on Classify.
Result<TactileMessage> DecodeTactileFrame(const CanFrame& frame);
// The same with `kind` = Classify(frame) already known.
Result<TactileMessage> DecodeTactileFrame(const CanFrame& frame, TactileFrameKind kind);

}  // namespace hilrig::rig
