// A protobuf message type as an MCAP channel, read back as a reader that has none of the rig's
// .proto files would: the schema's FileDescriptorSet alone rebuilds the message type (report.proto
// with scenario.proto, which it imports, before it), and the stored wire bytes decode to the
// message that was written.
#include "host/mcap/protobuf_channel.h"

#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <memory>
#include <sstream>

#include "host/mcap/mcap_reader.h"
#include "proto/report.pb.h"

namespace hilrig::mcap {
namespace {

proto::Report SampleReport(int i) {
  proto::Report report;
  report.set_scenario("balloon_grasp");
  report.set_seed(static_cast<std::uint64_t>(i));
  report.set_simulated_s(0.5 * i);
  proto::EnvelopeResult& envelope = *report.add_envelopes();
  envelope.set_name("grasp_force");
  envelope.set_signal(proto::GRASP_FORCE_N);  // an enum of the imported scenario.proto
  envelope.set_worst_value(0.6 + 0.001 * i);
  return report;
}

TEST(ProtobufChannelTest, TheSetHoldsTheFileAfterEveryFileItImports) {
  google::protobuf::FileDescriptorSet set;
  ASSERT_TRUE(set.ParseFromString(FileDescriptorSetOf(*proto::Report::descriptor())));
  ASSERT_EQ(set.file_size(), 2);
  EXPECT_EQ(set.file(0).name(), proto::Signal_descriptor()->file()->name());
  EXPECT_EQ(set.file(1).name(), proto::Report::descriptor()->file()->name());
}

TEST(ProtobufChannelTest, AReaderDecodesTheMessagesFromTheSchemaAlone) {
  std::ostringstream out;
  McapWriter writer(out);
  ASSERT_TRUE(writer.Open("", "hilrig test"));
  const auto channel = AddProtobufChannel(writer, *proto::Report::descriptor(), "/run/report");
  ASSERT_TRUE(channel) << channel.error().message;
  std::vector<std::string> written;
  for (int i = 0; i < 3; ++i) {
    written.push_back(SampleReport(i).SerializeAsString());
    MessageToWrite message;
    message.channel_id = channel.value();
    message.sequence = static_cast<std::uint32_t>(i);
    message.log_time_ns = static_cast<std::uint64_t>(i) * 1'000'000;
    message.payload = written.back();
    ASSERT_TRUE(writer.Write(message));
  }
  ASSERT_TRUE(writer.Close());

  const McapReadResult read = ReadMcap(out.str());
  ASSERT_TRUE(read.ok()) << read.error->detail;
  const McapChannel& stored = read.contents.channels.at(channel.value());
  EXPECT_EQ(stored.topic, "/run/report");
  EXPECT_EQ(stored.message_encoding, "protobuf");
  const McapSchema& schema = read.contents.schemas.at(stored.schema_id);
  EXPECT_EQ(schema.name, "hilrig.proto.Report");
  EXPECT_EQ(schema.encoding, "protobuf");

  // A pool of its own, built from the schema: nothing of the generated code.
  google::protobuf::FileDescriptorSet set;
  ASSERT_TRUE(set.ParseFromString(schema.data));
  google::protobuf::DescriptorPool pool;
  for (const google::protobuf::FileDescriptorProto& file : set.file()) {
    ASSERT_NE(pool.BuildFile(file), nullptr) << file.name();
  }
  const google::protobuf::Descriptor* type = pool.FindMessageTypeByName(schema.name);
  ASSERT_NE(type, nullptr);
  EXPECT_NE(type, proto::Report::descriptor());
  google::protobuf::DynamicMessageFactory factory(&pool);
  ASSERT_EQ(read.contents.messages.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    std::unique_ptr<google::protobuf::Message> decoded(factory.GetPrototype(type)->New());
    ASSERT_TRUE(decoded->ParseFromString(read.contents.messages[i].payload));
    EXPECT_EQ(decoded->SerializeAsString(), written[i]);
    proto::Report back;
    ASSERT_TRUE(back.ParseFromString(decoded->SerializeAsString()));
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(
        back, SampleReport(static_cast<int>(i))));
  }
}

}  // namespace
}  // namespace hilrig::mcap
