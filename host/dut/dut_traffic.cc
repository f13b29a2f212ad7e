#include "host/dut/dut_traffic.h"

namespace hilrig::host {

std::size_t RecordingCanBus::Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) {
  const std::size_t first = out.size();
  const std::size_t received = bus_->Receive(now_ns, out);
  for (std::size_t i = first; i < out.size(); ++i) sink_.Received(out[i]);
  return received;
}

RecordingDutPort::RecordingDutPort(std::unique_ptr<DutPort> dut, DutTrafficSink& sink,
                                   const rig::Clock* wall_clock)
    : dut_(std::move(dut)),
      sink_(sink),
      wall_clock_(wall_clock),
      wall_start_ns_(wall_clock != nullptr ? wall_clock->NowNs() : 0) {}

std::optional<std::int64_t> RecordingDutPort::WallNs() const {
  if (wall_clock_ == nullptr) return std::nullopt;
  return wall_clock_->NowNs() - wall_start_ns_;
}

// The step is told after the DUT has taken it: the CAN frames it drained from its bus for the step
// come before the step in the log, as a replay must hand them over.
rig::Result<ActuatorMessage> RecordingDutPort::Step(std::uint64_t tick, std::int64_t now_ns) {
  const std::optional<std::int64_t> asked_wall_ns = WallNs();
  rig::Result<ActuatorMessage> command = dut_->Step(tick, now_ns);
  sink_.Asked(tick, now_ns, asked_wall_ns);
  if (command) sink_.Answered(tick, now_ns, command.value(), WallNs());
  return command;
}

void RecordingDutPort::RequestStep(std::uint64_t tick, std::int64_t now_ns) {
  const std::optional<std::int64_t> asked_wall_ns = WallNs();
  dut_->RequestStep(tick, now_ns);
  sink_.Asked(tick, now_ns, asked_wall_ns);
  // A DUT that stops answering must not grow the queue: a command older than this many steps is
  // logged at its own stamp's time.
  if (awaiting_.size() >= kMaxAwaitedSteps) awaiting_.pop_front();
  awaiting_.push_back({tick, now_ns});
}

// A command answers the newest step it names; steps asked before it that never got theirs (the
// DUT skipped them) are dropped from the queue.
rig::Result<std::optional<ActuatorMessage>> RecordingDutPort::PollCommand() {
  rig::Result<std::optional<ActuatorMessage>> polled = dut_->PollCommand();
  if (!polled || !polled.value()) return polled;
  const ActuatorMessage& command = *polled.value();
  while (!awaiting_.empty() && awaiting_.front().tick < command.answers_sequence) {
    awaiting_.pop_front();
  }
  std::int64_t asked_ns = command.stamp.time_ns;
  if (!awaiting_.empty() && awaiting_.front().tick == command.answers_sequence) {
    asked_ns = awaiting_.front().now_ns;
    awaiting_.pop_front();
  }
  sink_.Answered(command.answers_sequence, asked_ns, command, WallNs());
  return polled;
}

}  // namespace hilrig::host
