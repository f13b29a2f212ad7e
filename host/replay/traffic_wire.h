// The DUT's traffic as protobuf wire bytes, written field by field (dut_link/wire_codec.h's
// Writer) without protobuf objects: a run's log takes some 4 400 of these messages a simulated
// second, and building, sizing and serializing nested protobuf messages for each cost the run more
// than its physics. The bytes parse as the messages the log's channels name (proto/hil_link.proto's
// inputs and ActuatorCommand, proto/run_log.proto's DutStepRequest, DutCommand and DutCanFrame),
// with every field written, zeros included; tests/host/replay/traffic_wire_test.cc parses each
// back and compares it with the protobuf library's own conversion.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "host/link/hil_messages.h"
#include "proto/run_log.pb.h"
#include "rig/can_frame.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {

// Larger than the largest message: a DutCommand (an ActuatorCommand with six force vectors) takes
// about 360 bytes, a CAN FD frame's DutCanFrame about 110.
inline constexpr std::size_t kMaxTrafficMessageBytes = 512;
using TrafficBuffer = std::array<std::uint8_t, kMaxTrafficMessageBytes>;

// Each writes one message into `buffer` and returns the bytes written (a view into it). None can
// fail: every message fits the buffer. None allocates; each is O(its fields).

// The payload message of the input's stream (ImuSample, VioPose, PositionSetpoint, ...).
std::span<const std::uint8_t> EncodeDutInput(const DutInput& input, TrafficBuffer& buffer);
// A DutStepRequest.
std::span<const std::uint8_t> EncodeStepRequest(std::uint64_t tick,
                                                std::optional<std::int64_t> wall_ns,
                                                TrafficBuffer& buffer);
// A DutCommand holding `command` as its ActuatorCommand.
std::span<const std::uint8_t> EncodeDutCommand(std::uint64_t tick,
                                               std::optional<std::int64_t> wall_ns,
                                               const ActuatorMessage& command,
                                               TrafficBuffer& buffer);
// The log's name for a kind of frame. Never fails.
proto::TactileFrameKind TactileFrameKindOf(rig::TactileFrameKind kind);
// A DutCanFrame: the frame and what the tactile protocol reads in it (a tactile sample id whose
// bytes do not decode is TACTILE_FRAME_MALFORMED).
std::span<const std::uint8_t> EncodeDutCanFrame(const rig::CanFrame& frame, TrafficBuffer& buffer);

}  // namespace hilrig::host
