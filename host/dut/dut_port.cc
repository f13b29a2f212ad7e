#include "host/dut/dut_port.h"

namespace hilrig::host {

void DutPort::RequestStep(std::uint64_t tick, std::int64_t now_ns) {
  immediate_answer_.emplace(Step(tick, now_ns));
}

rig::Result<std::optional<ActuatorMessage>> DutPort::PollCommand() {
  if (!immediate_answer_) return std::optional<ActuatorMessage>();
  rig::Result<ActuatorMessage> answer = std::move(*immediate_answer_);
  immediate_answer_.reset();
  if (!answer) return answer.error();
  return std::optional<ActuatorMessage>(std::move(answer).value());
}

}  // namespace hilrig::host
