// The HIL link's wire protocol, on bytes only (no sockets): proto/hil_link.proto messages framed
// for a stream as a varint length then the serialized LinkMessage, a hard size limit per message,
// an incremental decoder that takes the bytes in whatever chunks the transport delivers, and the
// link's safety checks (protocol version, per-stream sequence numbers) as named errors with
// counters. The conversions to and from the plain structs of host/link/hil_messages.h carry every
// double as a double, so that a DUT behind the link computes bit for bit what it would in process.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "host/link/hil_messages.h"
#include "proto/hil_link.pb.h"
#include "rig/metric.h"
#include "rig/result.h"

namespace hilrig::host {

// Larger than any message the link carries (a DutConfig is about 2 KiB), small enough that a
// corrupt length prefix cannot make a peer allocate much.
inline constexpr std::size_t kMaxLinkMessageBytes = 4096;

enum class LinkErrorKind {
  kOversized,   // the length prefix exceeds the limit; the stream cannot be trusted any more
  kMalformed,   // a bad length prefix, or bytes that do not parse as a LinkMessage
  kBadVersion,  // a header whose protocol_version is not kHilLinkProtocolVersion
  kSequenceGap,
  kDuplicate,   // the same sequence number as the stream's previous message
  kOutOfOrder,  // a sequence number older than the stream's previous message
};

// "oversized", "malformed", "bad_version", "sequence_gap", "duplicate", "out_of_order".
const char* LinkErrorName(LinkErrorKind kind);

struct LinkError {
  LinkErrorKind kind = LinkErrorKind::kMalformed;
  std::string detail;
  std::string Message() const;  // "<name>: <detail>"
};

// A link error as a rig::Error with `message`: code kLinkProtocol, the kind in its subcode, so
// that layers passing the error on keep what the peer did wrong.
rig::Error LinkProtocolError(LinkErrorKind kind, std::string message);
// The kind a kLinkProtocol error carries; nullopt for any other error.
std::optional<LinkErrorKind> LinkErrorKindOf(const rig::Error& error);

struct LinkCounters {
  std::uint64_t messages = 0;  // delivered to the caller
  std::uint64_t bytes = 0;     // fed to the decoder
  std::uint64_t oversized = 0;
  std::uint64_t malformed = 0;
  std::uint64_t bad_version = 0;
  std::uint64_t sequence_gaps = 0;
  std::uint64_t duplicates = 0;
  std::uint64_t out_of_order = 0;

  std::uint64_t errors() const {
    return oversized + malformed + bad_version + sequence_gaps + duplicates + out_of_order;
  }
};

// Named report metrics ("<prefix>messages", "<prefix>malformed", ...), for DutPort::link_metrics.
std::vector<rig::Metric> LinkCounterMetrics(const LinkCounters& counters,
                                            const std::string& prefix);

// The frame for `message`: varint length, then the message. Fails if the message is larger than
// max_message_bytes.
rig::Result<std::string> EncodeLinkFrame(const proto::LinkMessage& message,
                                         std::size_t max_message_bytes = kMaxLinkMessageBytes);

// The header of whichever payload the message holds; nullptr when it holds none.
const proto::LinkHeader* HeaderOf(const proto::LinkMessage& message);
proto::LinkHeader* MutableHeaderOf(proto::LinkMessage& message);

// One slot per LinkMessage payload field number, the highest being GnssFix's: a payload numbered
// past it must raise this (tests/host/link/hil_link_codec_test.cc checks every payload fits).
inline constexpr std::size_t kLinkPayloadSlots = proto::LinkMessage::kGnssFieldNumber + 1;

// Next sequence number per stream (payload type) on the sending side; stamps the header of the
// messages whose sequence the sender does not already track (hello, config, step, bye).
class LinkSequencer {
 public:
  // Sets header.protocol_version and, when `assign_sequence`, header.sequence from this stream's
  // counter. Messages carrying their own stamp (imu, vio, setpoint, command) pass false.
  void Stamp(proto::LinkMessage& message, std::int64_t time_ns, bool assign_sequence = true);

 private:
  std::array<std::uint64_t, kLinkPayloadSlots> next_{};
};

using LinkEvent = std::variant<proto::LinkMessage, LinkError>;

// Takes stream bytes in any chunking and yields the messages in them, or named errors. Each
// stream (payload type) must carry sequence numbers 0, 1, 2, ... in order. After an oversized or
// malformed frame the stream has lost its framing (or its peer is broken): the decoder yields
// that error once and nothing after it; the connection should be dropped. A version, gap,
// duplicate or out-of-order error concerns one message only; that message is withheld (a gap's
// message is withheld too, and the stream resynchronises on it), and decoding goes on.
class LinkDecoder {
 public:
  explicit LinkDecoder(std::size_t max_message_bytes = kMaxLinkMessageBytes);

  void Feed(std::span<const std::uint8_t> bytes);
  void Feed(const std::string& bytes);
  // The next message or error from the bytes fed so far; nullopt until more bytes are needed.
  std::optional<LinkEvent> Next();

  bool broken() const { return broken_; }
  // Bytes fed and not yet consumed by a complete frame.
  std::size_t buffered_bytes() const { return buffer_.size() - read_at_; }
  const LinkCounters& counters() const { return counters_; }

 private:
  std::optional<LinkEvent> Fail(LinkErrorKind kind, std::string detail);
  std::optional<LinkEvent> Check(proto::LinkMessage message);

  std::size_t max_message_bytes_;
  std::vector<std::uint8_t> buffer_;
  std::size_t read_at_ = 0;
  bool broken_ = false;
  std::array<std::optional<std::uint64_t>, kLinkPayloadSlots> last_{};
  LinkCounters counters_;
};

// Plain structs <-> protobuf. Every field; doubles as doubles.
proto::LinkMessage ToLink(const ActuatorMessage& message);
// The same into `command`, reusing what it already holds: a caller that keeps one message per
// stream converts without allocating after that stream's first message. Never fails.
void FillLink(const ActuatorMessage& message, proto::ActuatorCommand& command);
// Fails when the command does not carry exactly 4 rotor thrusts and 6 tactile forces (a missing
// vector field is zero, as proto3 reads it).
rig::Result<ActuatorMessage> FromLink(const proto::ActuatorCommand& message);

// Any input of the runner to the DUT, and back: the DutInput a link message carries, or nullopt
// when it carries another payload (hello, config, step, command, bye), so that a DUT behind the
// link takes every stream without naming it.
proto::LinkMessage ToLink(const DutInput& input);
void FillLink(const DutInput& input, proto::LinkMessage& link);  // likewise
// The LinkMessage field that carries DutInput alternative `input_index` (imu, vio, setpoint, ...):
// its name is the alternative's kStream, its message type the payload's.
const google::protobuf::FieldDescriptor& DutInputPayloadField(std::size_t input_index);
std::optional<DutInput> DutInputFromLink(const proto::LinkMessage& message);

// The sequence of the last message of DutInput alternative `input_index` the DUT had taken when
// it computed `command` (ActuatorCommand.last_<stream>_sequence); nullopt when it had taken none.
// The runner turns these into per-stream response latencies.
std::optional<std::uint64_t> LastTakenSequence(const proto::ActuatorCommand& command,
                                               std::size_t input_index);
void SetLastTakenSequence(proto::ActuatorCommand& command, std::size_t input_index,
                          std::uint64_t sequence);

}  // namespace hilrig::host
