#include "host/replay/recorded_traffic.h"

#include <algorithm>
#include <span>

#include "host/link/hil_link_codec.h"
#include "host/replay/dut_traffic_log.h"

namespace hilrig::host {
namespace {

std::int64_t SimulatedNs(const mcap::McapMessage& message) {
  return static_cast<std::int64_t>(message.log_time_ns) - kRunLogEpochNs;
}

rig::Result<rig::TimedCanFrame> FrameOf(const proto::DutCanFrame& frame, std::int64_t time_ns) {
  const std::size_t limit =
      frame.fd() ? rig::CanFrame::kMaxFdPayload : rig::CanFrame::kMaxClassicPayload;
  if (frame.data().size() > limit || frame.length() > limit ||
      (!frame.remote() && frame.length() != frame.data().size())) {
    return rig::MakeError("a CAN frame of " + std::to_string(frame.data().size()) +
                          " bytes with length " + std::to_string(frame.length()));
  }
  rig::TimedCanFrame timed;
  timed.time_ns = time_ns;
  rig::CanFrame& out = timed.frame;
  out.id = frame.id() & (frame.extended() ? rig::kMaxExtendedId : rig::kMaxStandardId);
  out.extended = frame.extended();
  out.remote = frame.remote();
  out.fd = frame.fd();
  out.bitrate_switch = frame.bitrate_switch();
  out.error_state_indicator = frame.error_state_indicator();
  out.error = frame.error();
  out.length = static_cast<std::uint8_t>(frame.length());
  std::copy(frame.data().begin(), frame.data().end(), out.data.begin());
  return timed;
}

}  // namespace

rig::Result<RecordedTraffic> RecordedTraffic::Of(const mcap::McapContents& contents) {
  RecordedTraffic traffic;
  std::optional<std::uint16_t> recording_channel;
  for (const auto& [id, channel] : contents.channels) {
    const auto schema = contents.schemas.find(channel.schema_id);
    const std::string schema_name = schema != contents.schemas.end() ? schema->second.name : "";
    const auto expect = [&](const google::protobuf::Descriptor& message) -> rig::Result<void> {
      if (schema_name == message.full_name()) return {};
      return rig::MakeError(channel.topic + " carries " + schema_name + ", not " +
                            message.full_name());
    };
    rig::Result<void> expected;
    if (channel.topic == kRecordingTopic) {
      expected = expect(*proto::RunRecording::descriptor());
      recording_channel = id;
    } else if (channel.topic == kDutCanTopic) {
      expected = expect(*proto::DutCanFrame::descriptor());
      traffic.channels_[id] = {Kind::kCan};
    } else if (channel.topic == kDutStepTopic) {
      expected = expect(*proto::DutStepRequest::descriptor());
      traffic.channels_[id] = {Kind::kStep};
    } else if (channel.topic == kDutCommandTopic) {
      expected = expect(*proto::DutCommand::descriptor());
      traffic.channels_[id] = {Kind::kCommand};
    } else {
      for (std::size_t index = 0; index < kDutInputStreams; ++index) {
        const google::protobuf::FieldDescriptor& field = DutInputPayloadField(index);
        if (channel.topic != kDutInputTopicPrefix + field.name()) continue;
        expected = expect(*field.message_type());
        traffic.channels_[id] = {Kind::kInput, index};
      }
    }
    if (!expected) return expected.error();
  }
  if (!recording_channel) {
    return rig::MakeError(std::string("no ") + kRecordingTopic +
                          " channel: not a run's log, or one written without its DUT's traffic");
  }
  const auto first = std::find_if(
      contents.messages.begin(), contents.messages.end(),
      [&](const mcap::McapMessage& message) { return message.channel_id == *recording_channel; });
  if (first == contents.messages.end() || !traffic.recording_.ParseFromString(first->payload)) {
    return rig::MakeError(std::string(kRecordingTopic) + " has no readable message");
  }
  return traffic;
}

rig::Result<std::optional<RecordedEvent>> RecordedTraffic::Decode(
    const mcap::McapMessage& message) const {
  const auto channel = channels_.find(message.channel_id);
  if (channel == channels_.end()) return std::optional<RecordedEvent>();
  const std::int64_t time_ns = SimulatedNs(message);
  const auto unreadable = [&message](const char* what) {
    return rig::MakeError(std::string(what) + " (message " + std::to_string(message.sequence) +
                          ") does not parse");
  };
  switch (channel->second.kind) {
    case Kind::kInput: {
      proto::LinkMessage link;
      const google::protobuf::FieldDescriptor& field =
          DutInputPayloadField(channel->second.input_index);
      if (!link.GetReflection()->MutableMessage(&link, &field)->ParseFromString(message.payload)) {
        return unreadable("a DUT input");
      }
      std::optional<DutInput> input = DutInputFromLink(link);
      if (!input) return unreadable("a DUT input");
      return std::optional<RecordedEvent>(std::move(*input));
    }
    case Kind::kCan: {
      proto::DutCanFrame frame;
      if (!frame.ParseFromString(message.payload)) return unreadable("a CAN frame");
      auto timed = FrameOf(frame, time_ns);
      if (!timed) return timed.error();
      return std::optional<RecordedEvent>(timed.value());
    }
    case Kind::kStep: {
      proto::DutStepRequest step;
      if (!step.ParseFromString(message.payload)) return unreadable("a step request");
      return std::optional<RecordedEvent>(RecordedStep{step.tick(), time_ns});
    }
    case Kind::kCommand: {
      proto::DutCommand command;
      if (!command.ParseFromString(message.payload)) return unreadable("a DUT command");
      auto decoded = FromLink(command.command());
      if (!decoded) return decoded.error();
      return std::optional<RecordedEvent>(
          RecordedCommand{command.tick(), time_ns, std::move(decoded).value()});
    }
  }
  return std::optional<RecordedEvent>();
}

}  // namespace hilrig::host
