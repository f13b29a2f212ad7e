#include "dut_emu/link_can_bus.h"

#include "rig/can_frame.h"

namespace hilrig::dut_emu {

void LinkCanBus::Deliver(std::span<const rig::CanFrame> frames) {
  queued_.insert(queued_.end(), frames.begin(), frames.end());
}

rig::Result<void> LinkCanBus::Send(const rig::CanFrame& frame, std::int64_t /*now_ns*/) {
  if (auto valid = rig::ValidateFrame(frame); !valid) {
    ++counters_.send_failures;
    return rig::MakeError("LinkCanBus: " + valid.error().message);
  }
  ++counters_.frames_sent;
  return {};
}

std::size_t LinkCanBus::Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) {
  const std::size_t before = out.size();
  for (const rig::CanFrame& frame : queued_) {
    const bool wanted =
        frame.error ? (frame.id & error_mask_) != 0 : rig::FilterAccepts(filters_, frame);
    if (wanted) out.push_back({frame, now_ns, false});
  }
  queued_.clear();
  const std::size_t appended = out.size() - before;
  counters_.frames_received += appended;
  return appended;
}

void LinkCanBus::SetFilters(std::span<const rig::CanFilter> filters) {
  filters_.assign(filters.begin(), filters.end());
}

void LinkCanBus::SetReceiveErrorFrames(bool enabled) {
  error_mask_ = enabled ? rig::kCanErrMask : 0;
}

void LinkCanBus::SetErrorFrameMask(std::uint32_t class_mask) { error_mask_ = class_mask; }

}  // namespace hilrig::dut_emu
