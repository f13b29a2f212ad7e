#include "rig/tactile_protocol.h"

#include <cstdio>
#include <string>

#include "rig/check.h"

namespace hilrig::rig {
namespace {

constexpr std::uint8_t kMaxGainSel = 7;
constexpr std::uint8_t kMaxResolution = 3;

bool IsSensorNode(std::uint32_t node_id) {
  return node_id >= tactile_bus::kFirstNodeId && node_id <= tactile_bus::kReferenceNodeId;
}

bool IsConfigTarget(std::uint32_t node_id) {
  return node_id == tactile_bus::kBroadcastNodeId || IsSensorNode(node_id);
}

void PutUint16Le(std::uint16_t value, std::uint8_t* out) {
  out[0] = static_cast<std::uint8_t>(value & 0xFF);
  out[1] = static_cast<std::uint8_t>(value >> 8);
}

std::uint16_t GetUint16Le(const std::uint8_t* in) {
  return static_cast<std::uint16_t>(in[0] | (in[1] << 8));
}

std::string Hex(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof(text), "0x%X", static_cast<unsigned>(value));
  return text;
}

// "tactile sample 0x103: " -- every complaint names the frame it is about.
std::string Prefix(const char* what, const CanFrame& frame) {
  return std::string("tactile ") + what + " " + Hex(frame.id) + ": ";
}

Error FlagError(const char* what, const CanFrame& frame) {
  if (frame.error) return MakeError(Prefix(what, frame) + "error frame, not a tactile frame");
  if (frame.remote) return MakeError(Prefix(what, frame) + "remote frame carries no data");
  if (frame.fd) return MakeError(Prefix(what, frame) + "expected a classic frame, got CAN FD");
  return MakeError(Prefix(what, frame) + "expected an 11-bit id, got an extended id");
}

bool IsClassicData(const CanFrame& frame) {
  return !frame.error && !frame.remote && !frame.fd && !frame.extended;
}

// Flags, id range and exact length of a sample or status frame; `classified` is Classify(frame),
// passed in so that a dispatcher which has classified the frame does not do it again.
Result<void> CheckNodeFrame(const CanFrame& frame, TactileFrameKind classified,
                            TactileFrameKind kind, const char* what, std::uint32_t base_id,
                            std::uint8_t length) {
  if (classified == TactileFrameKind::kNotClassicData) return FlagError(what, frame);
  if (classified != kind) {
    return MakeError(std::string("tactile ") + what + ": id " + Hex(frame.id) + " is outside the " +
                     what + " ids " + Hex(base_id + tactile_bus::kFirstNodeId) + ".." +
                     Hex(base_id + tactile_bus::kReferenceNodeId));
  }
  if (frame.length != length) {
    return MakeError(Prefix(what, frame) + "expected " + std::to_string(length) + " bytes, got " +
                     std::to_string(frame.length));
  }
  return {};
}

Error BadCommand(const CanFrame& frame, const std::string& problem) {
  return MakeError(Prefix("config", frame) + problem);
}

// The argument bytes of a command, checked for length and range.
Result<void> DecodeCommandArguments(const CanFrame& frame, TactileConfigCommand& out) {
  const std::uint8_t* args = &frame.data[1];
  switch (out.command) {
    case TactileCommand::kSetRate: {
      if (frame.length < 3) {
        return BadCommand(frame, "set-rate needs 3 bytes, got " + std::to_string(frame.length));
      }
      out.rate_hz = GetUint16Le(args);
      if (!TactileRateCodeFromHz(out.rate_hz)) {
        return BadCommand(frame, "rate " + std::to_string(out.rate_hz) + " Hz is not supported");
      }
      return {};
    }
    case TactileCommand::kSetGain:
      out.gain_sel = args[0];
      if (out.gain_sel > kMaxGainSel) {
        return BadCommand(frame, "gain_sel " + std::to_string(out.gain_sel) + " is not 0..7");
      }
      return {};
    case TactileCommand::kSetResolution:
      out.resolution = args[0];
      if (out.resolution > kMaxResolution) {
        return BadCommand(frame, "resolution " + std::to_string(out.resolution) + " is not 0..3");
      }
      return {};
    case TactileCommand::kZero:
    case TactileCommand::kReset:
      return {};  // byte 1 is reserved
  }
  return BadCommand(frame, "command " + std::to_string(frame.data[0]) + " is unknown");
}

bool IsKnownCommand(std::uint8_t command) {
  return command >= static_cast<std::uint8_t>(TactileCommand::kSetRate) &&
         command <= static_cast<std::uint8_t>(TactileCommand::kReset);
}

// The decoders below take Classify(frame) as `kind`.
Result<TactileSample> DecodeSampleOfKind(const CanFrame& frame, TactileFrameKind kind) {
  if (Result<void> checked = CheckNodeFrame(frame, kind, TactileFrameKind::kSample, "sample",
                                            tactile_bus::kSampleBaseId, tactile_bus::kSampleLength);
      !checked) {
    return checked.error();
  }
  TactileSample sample;
  sample.node_id = static_cast<std::uint8_t>(frame.id - tactile_bus::kSampleBaseId);
  for (int axis = 0; axis < 3; ++axis) sample.code[axis] = GetUint16Le(&frame.data[2 * axis]);
  sample.sequence = frame.data[6];
  sample.status = frame.data[7];
  return sample;
}

Result<TactileStatus> DecodeStatusOfKind(const CanFrame& frame, TactileFrameKind kind) {
  if (Result<void> checked = CheckNodeFrame(frame, kind, TactileFrameKind::kStatus, "status",
                                            tactile_bus::kStatusBaseId, tactile_bus::kStatusLength);
      !checked) {
    return checked.error();
  }
  TactileStatus status;
  status.node_id = static_cast<std::uint8_t>(frame.id - tactile_bus::kStatusBaseId);
  status.temperature_centi_c = static_cast<std::int16_t>(GetUint16Le(&frame.data[0]));
  status.flags = frame.data[2];
  status.gain_sel = frame.data[3];
  status.resolution = frame.data[4];
  status.rate_code = frame.data[5];
  status.rx_error_count = frame.data[6];
  status.firmware_version = frame.data[7];
  return status;
}

Result<TactileConfigCommand> DecodeConfigOfKind(const CanFrame& frame, TactileFrameKind kind) {
  if (kind == TactileFrameKind::kNotClassicData) return FlagError("config", frame);
  if (kind != TactileFrameKind::kConfig) {
    return MakeError("tactile config: id " + Hex(frame.id) + " is outside the config ids " +
                     Hex(tactile_bus::kConfigBaseId) + ".." +
                     Hex(tactile_bus::kConfigBaseId + tactile_bus::kReferenceNodeId));
  }
  if (frame.length < tactile_bus::kConfigMinLength ||
      frame.length > tactile_bus::kConfigMaxLength) {
    return BadCommand(frame, "expected 2..8 bytes, got " + std::to_string(frame.length));
  }
  if (!IsKnownCommand(frame.data[0])) {
    return BadCommand(frame, "command " + std::to_string(frame.data[0]) + " is unknown");
  }
  TactileConfigCommand command;
  command.node_id = static_cast<std::uint8_t>(frame.id - tactile_bus::kConfigBaseId);
  command.command = static_cast<TactileCommand>(frame.data[0]);
  if (Result<void> args = DecodeCommandArguments(frame, command); !args) return args.error();
  return command;
}

}  // namespace

std::optional<std::uint8_t> TactileRateCodeFromHz(std::uint16_t rate_hz) {
  for (std::size_t code = 0; code < tactile_bus::kRateHzByCode.size(); ++code) {
    if (tactile_bus::kRateHzByCode[code] == rate_hz) return static_cast<std::uint8_t>(code);
  }
  return std::nullopt;
}

std::optional<std::uint16_t> TactileRateHzFromCode(std::uint8_t rate_code) {
  if (rate_code >= tactile_bus::kRateHzByCode.size()) return std::nullopt;
  return tactile_bus::kRateHzByCode[rate_code];
}

TactileFrameKind Classify(const CanFrame& frame) {
  if (!IsClassicData(frame)) return TactileFrameKind::kNotClassicData;
  if (frame.id >= tactile_bus::kConfigBaseId &&
      IsConfigTarget(frame.id - tactile_bus::kConfigBaseId)) {
    return TactileFrameKind::kConfig;
  }
  if (frame.id > tactile_bus::kSampleBaseId &&
      IsSensorNode(frame.id - tactile_bus::kSampleBaseId)) {
    return TactileFrameKind::kSample;
  }
  if (frame.id > tactile_bus::kStatusBaseId &&
      IsSensorNode(frame.id - tactile_bus::kStatusBaseId)) {
    return TactileFrameKind::kStatus;
  }
  return TactileFrameKind::kUnknownId;
}

std::optional<std::uint8_t> TactileNodeOf(const CanFrame& frame) {
  return TactileNodeOf(frame, Classify(frame));
}

std::optional<std::uint8_t> TactileNodeOf(const CanFrame& frame, TactileFrameKind kind) {
  switch (kind) {
    case TactileFrameKind::kConfig:
      return static_cast<std::uint8_t>(frame.id - tactile_bus::kConfigBaseId);
    case TactileFrameKind::kSample:
      return static_cast<std::uint8_t>(frame.id - tactile_bus::kSampleBaseId);
    case TactileFrameKind::kStatus:
      return static_cast<std::uint8_t>(frame.id - tactile_bus::kStatusBaseId);
    default:
      return std::nullopt;
  }
}

CanFrame EncodeTactileSample(const TactileSample& sample) {
  HILRIG_CHECK(IsSensorNode(sample.node_id), "sample node id must be 1..7");
  std::array<std::uint8_t, tactile_bus::kSampleLength> bytes{};
  for (int axis = 0; axis < 3; ++axis) PutUint16Le(sample.code[axis], &bytes[2 * axis]);
  bytes[6] = sample.sequence;
  bytes[7] = sample.status;
  return CanFrame::Classic(tactile_bus::kSampleBaseId + sample.node_id, bytes);
}

CanFrame EncodeTactileStatus(const TactileStatus& status) {
  HILRIG_CHECK(IsSensorNode(status.node_id), "status node id must be 1..7");
  std::array<std::uint8_t, tactile_bus::kStatusLength> bytes{};
  PutUint16Le(static_cast<std::uint16_t>(status.temperature_centi_c), &bytes[0]);
  bytes[2] = status.flags;
  bytes[3] = status.gain_sel;
  bytes[4] = status.resolution;
  bytes[5] = status.rate_code;
  bytes[6] = status.rx_error_count;
  bytes[7] = status.firmware_version;
  return CanFrame::Classic(tactile_bus::kStatusBaseId + status.node_id, bytes);
}

CanFrame EncodeTactileConfig(const TactileConfigCommand& command) {
  HILRIG_CHECK(IsConfigTarget(command.node_id), "config node id must be 0 (broadcast) or 1..7");
  std::array<std::uint8_t, tactile_bus::kConfigMaxLength> bytes{};
  bytes[0] = static_cast<std::uint8_t>(command.command);
  switch (command.command) {
    case TactileCommand::kSetRate:
      HILRIG_CHECK(TactileRateCodeFromHz(command.rate_hz).has_value(), "unsupported rate_hz");
      PutUint16Le(command.rate_hz, &bytes[1]);
      break;
    case TactileCommand::kSetGain:
      HILRIG_CHECK(command.gain_sel <= kMaxGainSel, "gain_sel must be 0..7");
      bytes[1] = command.gain_sel;
      break;
    case TactileCommand::kSetResolution:
      HILRIG_CHECK(command.resolution <= kMaxResolution, "resolution must be 0..3");
      bytes[1] = command.resolution;
      break;
    case TactileCommand::kZero:
    case TactileCommand::kReset:
      break;
    default:
      HILRIG_CHECK(false, "unknown tactile command");
  }
  return CanFrame::Classic(tactile_bus::kConfigBaseId + command.node_id, bytes);
}

Result<TactileSample> DecodeTactileSample(const CanFrame& frame) {
  return DecodeSampleOfKind(frame, Classify(frame));
}

Result<TactileStatus> DecodeTactileStatus(const CanFrame& frame) {
  return DecodeStatusOfKind(frame, Classify(frame));
}

Result<TactileConfigCommand> DecodeTactileConfig(const CanFrame& frame) {
  return DecodeConfigOfKind(frame, Classify(frame));
}

Result<TactileMessage> DecodeTactileFrame(const CanFrame& frame) {
  return DecodeTactileFrame(frame, Classify(frame));
}

Result<TactileMessage> DecodeTactileFrame(const CanFrame& frame, TactileFrameKind kind) {
  switch (kind) {
    case TactileFrameKind::kSample: {
      Result<TactileSample> sample = DecodeSampleOfKind(frame, kind);
      if (!sample) return sample.error();
      return TactileMessage(sample.value());
    }
    case TactileFrameKind::kStatus: {
      Result<TactileStatus> status = DecodeStatusOfKind(frame, kind);
      if (!status) return status.error();
      return TactileMessage(status.value());
    }
    case TactileFrameKind::kConfig: {
      Result<TactileConfigCommand> command = DecodeConfigOfKind(frame, kind);
      if (!command) return command.error();
      return TactileMessage(command.value());
    }
    case TactileFrameKind::kUnknownId:
      return MakeError("tactile frame " + Hex(frame.id) + ": id is not a tactile id");
    case TactileFrameKind::kNotClassicData:
      break;
  }
  return FlagError("frame", frame);
}

}  // namespace hilrig::rig
