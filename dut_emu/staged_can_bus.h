// The DUT's CAN bus inside dut_emu, as InProcessDut would see it. The runner forwards every frame
// that reached the DUT's endpoint of its emulated bus over the loopback UDP bus and announces it,
// with the time it arrived there, in the next step request. The DUT must see the announced frames
// of a step at that step, stamped with those times. Datagrams and requests travel on different
// sockets, so a frame can be read before the request that announces it (a DUT process that was
// descheduled finds later steps' frames already in its socket) or after it (a datagram still on
// its way). Frames and announcements are therefore matched one to one, in order: a frame is handed
// to the DUT at the first step from its announcement on, with the runner's time; one that came
// early waits for its step, instead of being consumed ahead of time with the wrong time (which made
// every node look stale once the DUT had caught up); one that comes late reaches the first step
// after it arrives, still with the runner's time.
//
// A real bus (SocketCAN with sensor nodes on a bench, or the frames of `hilrig run --can`) is built
// with UnannouncedFrames::kPassThrough: every frame passes straight through with the inner bus's
// own stamp, and announcements are ignored. Frames on a real bus reach the DUT when the bus
// delivers them, not at a step; pairing them with announcements would, once the DUT fell a step
// behind, hand a later step's frames over unannounced and leave their announcements waiting for
// frames that never come, so that every step after it waits out its frame timeout.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <vector>

#include "rig/can_bus.h"

namespace hilrig::dut_emu {

// What a frame that arrives with no announcement waiting for it is.
enum class UnannouncedFrames {
  kEarly,        // every frame is announced (the runner's UDP forwarder): it waits for its step
  kPassThrough,  // a real bus: every frame goes to the DUT with the bus's stamp, none waits
};

class StagedCanBus final : public rig::CanBus {
 public:
  StagedCanBus(std::unique_ptr<rig::CanBus> inner, UnannouncedFrames unannounced);

  // A step's announcement: the runner's arrival times of the frames it forwarded, in order.
  // Ignored on a kPassThrough bus.
  void Announce(std::span<const std::int64_t> times_ns);
  // Reads what the inner bus holds and matches it with the announcements.
  void Pump(std::int64_t now_ns);
  // Announced frames that have not arrived yet.
  std::size_t missing() const { return unmatched_times_ns_.size(); }
  // Frames that arrived ahead of their announcement.
  std::size_t early() const { return early_.size(); }
  // Frames handed to the DUT so far: what its commands say they consumed.
  std::uint64_t handed_over() const { return handed_over_; }

  rig::Result<void> Send(const rig::CanFrame& frame, std::int64_t now_ns) override;
  // Hands over the frames matched so far (after a Pump at now_ns), never an early one.
  std::size_t Receive(std::int64_t now_ns, std::vector<rig::TimedCanFrame>& out) override;
  void SetFilters(std::span<const rig::CanFilter> filters) override;
  void SetReceiveErrorFrames(bool enabled) override;
  void SetErrorFrameMask(std::uint32_t class_mask) override;
  rig::Result<void> SetReceiveOwnFrames(bool enabled) override;
  rig::BusState state() const override { return inner_->state(); }
  rig::BusCounters counters() const override { return inner_->counters(); }

 private:
  // Pairs early frames with waiting announcements, oldest with oldest.
  void MatchEarlyFrames();

  std::unique_ptr<rig::CanBus> inner_;
  UnannouncedFrames unannounced_;
  std::deque<std::int64_t> unmatched_times_ns_;
  std::deque<rig::TimedCanFrame> early_;
  std::vector<rig::TimedCanFrame> ready_;
  std::vector<rig::TimedCanFrame> incoming_;
  std::uint64_t handed_over_ = 0;
};

}  // namespace hilrig::dut_emu
