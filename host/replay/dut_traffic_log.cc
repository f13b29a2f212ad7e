#include "host/replay/dut_traffic_log.h"

#include "host/link/hil_link_codec.h"

namespace hilrig::host {

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
  const google::protobuf::FieldDescriptor& field = DutInputPayloadField(stream);
  if (auto channel = Channel(input_channels_[stream], *field.message_type(),
                             kDutInputTopicPrefix + field.name())) {
    log_.LogBytes(*channel, StampOf(input).time_ns, EncodeDutInput(input, buffer_));
  }
}

void DutTrafficLog::Received(const rig::TimedCanFrame& frame) {
  if (auto channel = Channel(can_channel_, *proto::DutCanFrame::descriptor(), kDutCanTopic)) {
    log_.LogBytes(*channel, frame.time_ns, EncodeDutCanFrame(frame.frame, buffer_));
  }
}

void DutTrafficLog::Asked(std::uint64_t tick, std::int64_t now_ns,
                          std::optional<std::int64_t> wall_ns) {
  if (auto channel = Channel(step_channel_, *proto::DutStepRequest::descriptor(), kDutStepTopic)) {
    log_.LogBytes(*channel, now_ns, EncodeStepRequest(tick, wall_ns, buffer_));
  }
}

void DutTrafficLog::Answered(std::uint64_t tick, std::int64_t now_ns,
                             const ActuatorMessage& command, std::optional<std::int64_t> wall_ns) {
  if (auto channel =
          Channel(command_channel_, *proto::DutCommand::descriptor(), kDutCommandTopic)) {
    log_.LogBytes(*channel, now_ns, EncodeDutCommand(tick, wall_ns, command, buffer_));
  }
}

}  // namespace hilrig::host
