#include "dut_emu/staged_can_bus.h"

#include <utility>

namespace hilrig::dut_emu {

StagedCanBus::StagedCanBus(std::unique_ptr<rig::CanBus> inner, UnannouncedFrames unannounced)
    : inner_(std::move(inner)), unannounced_(unannounced) {}

void StagedCanBus::Announce(std::span<const std::int64_t> times_ns) {
  if (unannounced_ == UnannouncedFrames::kPassThrough) return;
  unmatched_times_ns_.insert(unmatched_times_ns_.end(), times_ns.begin(), times_ns.end());
  MatchEarlyFrames();
}

void StagedCanBus::MatchEarlyFrames() {
  while (!early_.empty() && !unmatched_times_ns_.empty()) {
    rig::TimedCanFrame frame = early_.front();
    early_.pop_front();
    frame.time_ns = unmatched_times_ns_.front();
    unmatched_times_ns_.pop_front();
    ready_.push_back(frame);
  }
}

void StagedCanBus::Pump(std::int64_t now_ns) {
  incoming_.clear();
  inner_->Receive(now_ns, incoming_);
  for (rig::TimedCanFrame& frame : incoming_) {
    if (!unmatched_times_ns_.empty()) {
      frame.time_ns = unmatched_times_ns_.front();
      unmatched_times_ns_.pop_front();
      ready_.push_back(frame);
    } else if (unannounced_ == UnannouncedFrames::kEarly) {
      early_.push_back(frame);
    } else {
      ready_.push_back(frame);
    }
  }
}

rig::Result<void> StagedCanBus::Send(const rig::CanFrame& frame, std::int64_t now_ns) {
  return inner_->Send(frame, now_ns);
}

std::size_t StagedCanBus::Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) {
  Pump(now_ns);
  const std::size_t handed = ready_.size();
  out.insert(out.end(), ready_.begin(), ready_.end());
  ready_.clear();
  handed_over_ += handed;
  return handed;
}

void StagedCanBus::SetFilters(std::span<const rig::CanFilter> filters) {
  inner_->SetFilters(filters);
}

void StagedCanBus::SetReceiveErrorFrames(bool enabled) { inner_->SetReceiveErrorFrames(enabled); }

void StagedCanBus::SetErrorFrameMask(std::uint32_t class_mask) {
  inner_->SetErrorFrameMask(class_mask);
}

rig::Result<void> StagedCanBus::SetReceiveOwnFrames(bool enabled) {
  return inner_->SetReceiveOwnFrames(enabled);
}

}  // namespace hilrig::dut_emu
