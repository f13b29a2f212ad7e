// EmulatedBus is an in-process CAN medium for lockstep runs: any number of endpoints (DUT,
// device emulators, loggers) connect to it and see each other's frames with realistic wire
// timing, and no OS, socket or thread is involved, so a run is deterministic.
//
// Timing: the medium serializes frames. A frame sent at now_ns starts at max(now_ns, the time
// the bus becomes free) and finishes FrameDurationNs later; every other endpoint (and the sender
// too if receive_own_frames) gets it stamped with the finish time, and Receive(now) returns only
// frames whose finish time is <= now. Frames are therefore queued at send time and merely become
// visible later; filters are applied when the frame is queued.
//
// Not yet modelled (later issues): priority arbitration among simultaneously pending frames,
// fault injection and TX queue limits. They belong in the medium's scheduling step, which is the
// single place that decides when a sent frame occupies the wire.
//
// Threading: endpoints and the bus are single-threaded by design (the runner drives everything
// in lockstep), so there are no mutexes. Use them from one thread only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "rig/can_bus.h"

namespace hilrig::rig {

struct EmulatedBusConfig {
  std::int64_t nominal_bitrate_bps = 1'000'000;
  std::int64_t data_bitrate_bps = 1'000'000;
  std::size_t rx_queue_capacity = 4096;  // per endpoint; excess frames are dropped and counted
  bool receive_own_frames = false;
};

// busy_ns is the sum of frame durations, so bus load = busy_ns / elapsed time.
struct EmulatedBusStats {
  std::uint64_t frames = 0;
  std::int64_t busy_ns = 0;
};

class EmulatedMedium;

class EmulatedBus {
 public:
  explicit EmulatedBus(EmulatedBusConfig config = {});
  // Aborts if endpoints are still connected: they would point at a dead medium.
  ~EmulatedBus();
  EmulatedBus(EmulatedBus&&) noexcept;
  EmulatedBus& operator=(EmulatedBus&&) noexcept;
  EmulatedBus(const EmulatedBus&) = delete;
  EmulatedBus& operator=(const EmulatedBus&) = delete;

  // A new node on the bus; the endpoint must not outlive the bus. Destroying the endpoint
  // detaches it, frames still queued for it are discarded. Name is for diagnostics.
  std::unique_ptr<CanBus> Connect(std::string name);
  EmulatedBusStats stats() const;

 private:
  // Behind a pointer so endpoints keep a stable address to it when the bus is moved.
  std::unique_ptr<EmulatedMedium> medium_;
};

}  // namespace hilrig::rig
