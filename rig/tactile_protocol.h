// The tactile bus protocol: the three kinds of classic CAN frame that the seven Hall sensor nodes
// and the host exchange, and the one codec in rig/ that knows their byte layout. proto/tactile.dbc
// states the same layout for other tools (tests/rig/tactile_dbc_test.cc keeps the two in step) and
// proto/TACTILE_PROTOCOL.md explains it. dut_fw/sensor_node.h is the node side of the same
// protocol; it repeats the constants because dut_fw may not depend on rig, and the cross-check
// test in tests/rig/tactile_protocol_test.cc decodes the node's frames with this codec.
//
// All ids are standard 11-bit ids, and a lower id wins arbitration, so configuration commands
// (0x080 + node) beat samples (0x100 + node), which beat the 1 Hz status frames (0x180 + node),
// and within a kind node 1 beats node 7. Multi-byte fields are little-endian. Decoders never abort
// on what arrives from a bus: every malformed frame comes back as an Error that names the problem.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <variant>

#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

inline constexpr std::uint8_t kFirstTactileNodeId = 1;
inline constexpr std::uint8_t kLastTactileNodeId = 6;
inline constexpr std::uint8_t kReferenceNodeId = 7;
inline constexpr std::uint8_t kTactileBroadcastNodeId = 0;  // config commands only

inline constexpr std::uint32_t kTactileConfigBaseId = 0x080;  // host -> node; +0 is broadcast
inline constexpr std::uint32_t kTactileSampleBaseId = 0x100;  // node -> bus, one per sample
inline constexpr std::uint32_t kTactileStatusBaseId = 0x180;  // node -> bus, 1 Hz and on command

inline constexpr std::uint8_t kTactileSampleLength = 8;
inline constexpr std::uint8_t kTactileStatusLength = 8;
inline constexpr std::uint8_t kTactileConfigMinLength = 2;
inline constexpr std::uint8_t kTactileConfigMaxLength = 8;

// Sample status bits. Bits the decoder does not know are passed through, so newer node firmware
// does not break an older host.
inline constexpr std::uint8_t kSampleStatusSaturated = 1u << 0;        // an axis at a rail
inline constexpr std::uint8_t kSampleStatusConversionError = 1u << 1;  // chip flagged ERROR
inline constexpr std::uint8_t kSampleStatusStale = 1u << 2;  // chip did not answer: last result
inline constexpr std::uint8_t kSampleStatusTare = 1u << 3;   // first sample after a zero request

// Status-frame flag bits.
inline constexpr std::uint8_t kNodeFlagChipError = 1u << 0;        // last chip transaction failed
inline constexpr std::uint8_t kNodeFlagConfigPending = 1u << 1;    // accepted, not yet on chip
inline constexpr std::uint8_t kNodeFlagCommandRejected = 1u << 2;  // last command was invalid
inline constexpr std::uint8_t kNodeFlagTarePending = 1u << 3;      // tare mark not yet sent
inline constexpr std::uint8_t kNodeFlagForwardOverflow = 1u << 4;  // daisy-chain drop since last

// The node's sample rates. The set-rate command carries Hz, the status frame the code; a rate not
// in this table is rejected, so host and node never disagree about what rate is running.
inline constexpr std::array<std::uint16_t, 11> kTactileRateHzByCode = {0,   1,   10,  20,  25,  50,
                                                                       100, 200, 250, 500, 1000};
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
  std::uint8_t rate_code = 0;            // index into kTactileRateHzByCode
  std::uint8_t rx_error_count = 0;       // frames the node rejected, saturating at 255
  std::uint8_t firmware_version = 0;     // major in the high nibble, minor in the low

  friend bool operator==(const TactileStatus&, const TactileStatus&) = default;
};

enum class TactileCommand : std::uint8_t {
  kSetRate = 1,        // u16 rate_hz, one of kTactileRateHzByCode
  kSetGain = 2,        // u8 gain_sel, 0..7
  kSetResolution = 3,  // u8 resolution, 0..3
  kZero = 4,           // tare: the node marks its next sample with kSampleStatusTare
  kReset = 5,          // defaults restored, sequence restarts at 0
};

struct TactileConfigCommand {
  std::uint8_t node_id = 0;  // 1..7, or kTactileBroadcastNodeId for all nodes
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
