#include "host/mcap/protobuf_channel.h"

#include <google/protobuf/descriptor.pb.h>

#include <set>

namespace hilrig::mcap {
namespace {

// Depth first over the imports, so that a file comes after everything it imports: a reader
// builds the files into its pool in the set's order, and a file needs its imports there first.
void AddWithImports(const google::protobuf::FileDescriptor& file, std::set<std::string>& added,
                    google::protobuf::FileDescriptorSet& set) {
  if (!added.insert(file.name()).second) return;
  for (int i = 0; i < file.dependency_count(); ++i) {
    AddWithImports(*file.dependency(i), added, set);
  }
  file.CopyTo(set.add_file());
}

}  // namespace

std::string FileDescriptorSetOf(const google::protobuf::Descriptor& message) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  AddWithImports(*message.file(), added, set);
  return set.SerializeAsString();
}

rig::Result<std::uint16_t> AddProtobufSchema(McapWriter& writer,
                                             const google::protobuf::Descriptor& message) {
  return writer.AddSchema(message.full_name(), kProtobufEncoding, FileDescriptorSetOf(message));
}

rig::Result<std::uint16_t> AddProtobufChannel(McapWriter& writer,
                                              const google::protobuf::Descriptor& message,
                                              std::string_view topic) {
  auto schema = AddProtobufSchema(writer, message);
  if (!schema) return schema.error();
  return writer.AddChannel(schema.value(), topic, kProtobufEncoding);
}

}  // namespace hilrig::mcap
