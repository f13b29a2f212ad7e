#include "host/runner/command_exchange.h"

#include <utility>

namespace hilrig::host {

rig::Result<bool> LockstepExchange::Arrived(DutPort& /*dut*/, ActuatorMessage& /*command*/) {
  return false;
}

rig::Result<bool> LockstepExchange::Ask(DutPort& dut, std::uint64_t tick, std::int64_t now_ns,
                                        ActuatorMessage& command) {
  auto answer = dut.Step(tick, now_ns);
  if (!answer) return answer.error();
  command = std::move(answer).value();
  return true;
}

void RealtimeExchange::Collect(DutPort& dut) {
  if (failure_) return;
  auto polled = dut.PollCommand();
  if (!polled) {
    failure_ = polled.error();
  } else if (polled.value()) {
    arrived_ = std::move(*polled.value());
  }
}

rig::Result<bool> RealtimeExchange::Arrived(DutPort& dut, ActuatorMessage& command) {
  Collect(dut);  // what came since the last wait slice
  if (failure_) return *failure_;
  pacer_.CountControlTick(arrived_.has_value());
  if (!arrived_) return false;
  command = std::move(*arrived_);
  arrived_.reset();
  return true;
}

rig::Result<bool> RealtimeExchange::Ask(DutPort& dut, std::uint64_t tick, std::int64_t now_ns,
                                        ActuatorMessage& /*command*/) {
  dut.RequestStep(tick, now_ns);  // a failure sticks in the port, for the next poll to report
  return false;
}

std::unique_ptr<CommandExchange> MakeCommandExchange(RealtimePacer* pacer) {
  if (pacer == nullptr) return std::make_unique<LockstepExchange>();
  return std::make_unique<RealtimeExchange>(*pacer);
}

}  // namespace hilrig::host
