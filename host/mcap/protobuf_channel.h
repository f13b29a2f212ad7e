// A protobuf message type as an MCAP channel: the schema a reader needs to decode the channel's
// messages without the rig's .proto files. MCAP's protobuf profile names the schema by the
// message's full name, gives it encoding "protobuf" and, as its data, a serialized
// google.protobuf.FileDescriptorSet that holds the message's file and every file it imports
// (Foxglove and @mcap/core build their decoders from it); the channel's message encoding is
// "protobuf" and each message is the type's wire bytes.
#pragma once

#include <google/protobuf/descriptor.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "host/mcap/mcap_writer.h"
#include "rig/result.h"

namespace hilrig::mcap {

inline constexpr std::string_view kProtobufEncoding = "protobuf";

// The serialized FileDescriptorSet of `message`'s file and of every file it imports, directly or
// not, each once, imports before the files that import them. Never fails; allocates the set.
std::string FileDescriptorSetOf(const google::protobuf::Descriptor& message);

// Adds the schema of `message`; returns its id, for channels that share it. Fails as
// McapWriter::AddSchema fails; allocates the schema's data.
rig::Result<std::uint16_t> AddProtobufSchema(McapWriter& writer,
                                             const google::protobuf::Descriptor& message);

// Adds the schema of `message` and a channel on `topic` that carries it; returns the channel's
// id. Fails as McapWriter::AddSchema and AddChannel fail (the stream, too many of them);
// allocates the schema's data.
rig::Result<std::uint16_t> AddProtobufChannel(McapWriter& writer,
                                              const google::protobuf::Descriptor& message,
                                              std::string_view topic);

}  // namespace hilrig::mcap
