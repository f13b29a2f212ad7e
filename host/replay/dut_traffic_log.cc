#include "host/replay/dut_traffic_log.h"

#include "host/link/hil_link_codec.h"
#include "rig/tactile_protocol.h"

namespace hilrig::host {
namespace {

proto::TactileFrameKind KindOf(rig::TactileFrameKind kind) {
  switch (kind) {
    case rig::TactileFrameKind::kSample:
      return proto::TACTILE_FRAME_SAMPLE;
    case rig::TactileFrameKind::kStatus:
      return proto::TACTILE_FRAME_STATUS;
    case rig::TactileFrameKind::kConfig:
      return proto::TACTILE_FRAME_CONFIG;
    case rig::TactileFrameKind::kUnknownId:
      return proto::TACTILE_FRAME_UNKNOWN_ID;
    case rig::TactileFrameKind::kNotClassicData:
      return proto::TACTILE_FRAME_NOT_CLASSIC_DATA;
  }
  return proto::TACTILE_FRAME_KIND_UNSPECIFIED;
}

}  // namespace

void FillDutCanFrame(const rig::CanFrame& frame, proto::DutCanFrame& out) {
  out.set_id(frame.id);
  out.set_extended(frame.extended);
  out.set_remote(frame.remote);
  out.set_fd(frame.fd);
  out.set_bitrate_switch(frame.bitrate_switch);
  out.set_error_state_indicator(frame.error_state_indicator);
  out.set_error(frame.error);
  out.set_length(frame.length);
  const std::span<const std::uint8_t> payload = frame.payload();
  out.mutable_data()->assign(payload.begin(), payload.end());
  const rig::TactileFrameKind kind = rig::Classify(frame);
  out.set_kind(KindOf(kind));
  out.clear_field_code();
  out.set_node_id(rig::TactileNodeOf(frame, kind).value_or(0));
  out.set_sample_sequence(0);
  out.set_sample_status(0);
  if (kind != rig::TactileFrameKind::kSample) return;
  const rig::Result<rig::TactileSample> sample = rig::DecodeTactileSample(frame);
  if (!sample) {
    out.set_kind(proto::TACTILE_FRAME_MALFORMED);
    return;
  }
  for (std::uint16_t code : sample.value().code) out.add_field_code(code);
  out.set_sample_sequence(sample.value().sequence);
  out.set_sample_status(sample.value().status);
}

rig::Result<std::unique_ptr<DutTrafficLog>> DutTrafficLog::Open(
    RunLogWriter& log, const proto::RunRecording& recording) {
  std::unique_ptr<DutTrafficLog> traffic(new DutTrafficLog(log));
  auto channel = log.AddChannel(*proto::RunRecording::descriptor(), kRecordingTopic);
  if (!channel) return channel.error();
  log.Log(channel.value(), 0, recording);
  return traffic;
}

std::optional<std::uint16_t> DutTrafficLog::Channel(std::optional<std::uint16_t>& id,
                                                    const google::protobuf::Descriptor& message,
                                                    const std::string& topic) {
  if (!id) {
    auto added = log_.AddChannel(message, topic);
    if (!added) return std::nullopt;
    id = added.value();
  }
  return id;
}

void DutTrafficLog::Sent(const DutInput& input) {
  const std::size_t stream = input.index();
  proto::LinkMessage& link = inputs_[stream];
  FillLink(input, link);
  const google::protobuf::FieldDescriptor& field = DutInputPayloadField(stream);
  const google::protobuf::Message& payload = link.GetReflection()->GetMessage(link, &field);
  if (auto channel = Channel(input_channels_[stream], *field.message_type(),
                             kDutInputTopicPrefix + field.name())) {
    log_.Log(*channel, StampOf(input).time_ns, payload);
  }
}

void DutTrafficLog::Received(const rig::TimedCanFrame& frame) {
  FillDutCanFrame(frame.frame, frame_);
  if (auto channel = Channel(can_channel_, *proto::DutCanFrame::descriptor(), kDutCanTopic)) {
    log_.Log(*channel, frame.time_ns, frame_);
  }
}

void DutTrafficLog::Asked(std::uint64_t tick, std::int64_t now_ns,
                          std::optional<std::int64_t> wall_ns) {
  step_.set_tick(tick);
  if (wall_ns) step_.set_wall_time_ns(*wall_ns);
  if (auto channel = Channel(step_channel_, *proto::DutStepRequest::descriptor(), kDutStepTopic)) {
    log_.Log(*channel, now_ns, step_);
  }
}

void DutTrafficLog::Answered(std::uint64_t tick, std::int64_t now_ns,
                             const ActuatorMessage& command, std::optional<std::int64_t> wall_ns) {
  command_.set_tick(tick);
  if (wall_ns) command_.set_wall_time_ns(*wall_ns);
  FillLink(command, *command_.mutable_command());
  if (auto channel =
          Channel(command_channel_, *proto::DutCommand::descriptor(), kDutCommandTopic)) {
    log_.Log(*channel, now_ns, command_);
  }
}

}  // namespace hilrig::host
