// The bus endpoint a replayed DUT reads: the recorded frames, each handed over at the time the DUT
// first took it in the recorded run. What the DUT sends goes nowhere (no sensor answers a replay)
// and is counted. Filters are not applied: the recorded frames are the ones that passed the
// DUT's filters in the run.
#pragma once

#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include "rig/can_bus.h"

namespace hilrig::host {

class ReplayCanBus final : public rig::CanBus {
 public:
  // Queues a recorded frame; frames are pushed in the order the DUT took them.
  void Push(const rig::TimedCanFrame& frame) { queued_.push_back(frame); }

  rig::Result<void> Send(const rig::CanFrame& frame, std::int64_t now_ns) override;
  // The queued frames that had arrived by `now_ns`, oldest first.
  std::size_t Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) override;
  void SetFilters(std::span<const rig::CanFilter> filters) override { (void)filters; }
  void SetReceiveErrorFrames(bool enabled) override { (void)enabled; }
  rig::BusState state() const override { return rig::BusState::kErrorActive; }
  rig::BusCounters counters() const override { return counters_; }

  std::size_t queued() const { return queued_.size(); }

 private:
  std::deque<rig::TimedCanFrame> queued_;
  rig::BusCounters counters_;
};

}  // namespace hilrig::host
