// The DUT's CAN bus inside dut_emu on the shared-memory link, where the runner puts each step's
// tactile frames in the step request itself: the session hands them in (Deliver) and the bus
// gives them to the DUT like the loopback UDP bus would (the same filters and error-frame mask),
// stamped with the time of the Receive; StagedCanBus then restamps them with the announced
// arrival times, as for the UDP bus. Frames the DUT sends go nowhere, as on the UDP bus, where
// the runner's forwarder never reads them; they are counted.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rig/can_bus.h"

namespace hilrig::dut_emu {

class LinkCanBus final : public rig::CanBus {
 public:
  // Queues frames for the next Receive. No allocation once the queue has grown to a step's size.
  void Deliver(std::span<const rig::CanFrame> frames);

  // Fails on an invalid frame (counted), else counts it and drops it.
  rig::Result<void> Send(const rig::CanFrame& frame, std::int64_t now_ns) override;
  std::size_t Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) override;
  void SetFilters(std::span<const rig::CanFilter> filters) override;
  void SetReceiveErrorFrames(bool enabled) override;
  void SetErrorFrameMask(std::uint32_t class_mask) override;
  rig::BusState state() const override { return rig::BusState::kErrorActive; }
  rig::BusCounters counters() const override { return counters_; }

 private:
  std::vector<rig::CanFrame> queued_;
  std::vector<rig::CanFilter> filters_;
  std::uint32_t error_mask_ = 0;
  rig::BusCounters counters_;
};

}  // namespace hilrig::dut_emu
