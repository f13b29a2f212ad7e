// EmulatedBus is an in-process CAN medium for lockstep runs: any number of endpoints (DUT,
// device emulators, loggers) connect to it and see each other's frames with realistic wire
// timing, arbitration, error handling and injected faults, and no OS, socket or thread is
// involved, so a run is deterministic.
//
// Timing: each endpoint has a bounded TX queue, sent in order like a socket's qdisc. Whenever the
// wire is free, the queue heads that are waiting compete and the lowest arbitration value wins
// (base id first, then a standard frame before an extended one with the same base id, a data
// frame before a remote one), so on a loaded bus high ids wait; equal values go to the endpoint
// connected first instead of colliding. A frame finishes FrameDurationNs after it starts, and
// every endpoint that wants it gets it stamped with the finish time; Receive(now) returns frames
// finished by now. Time flows in through Send/Receive/AdvanceTo: the wire is decided up to the
// latest time seen, but a frame starting exactly at that time is only decided once time moves
// past it, because another endpoint may still queue a higher-priority frame for the same instant.
// Time never runs backwards for the bus: a call stamped earlier than one already seen acts at
// the latest time seen.
//
// Error handling follows the CAN fault confinement rules closely enough for tests: a corrupted
// frame (see bus_fault_injection.h) raises the sender's TEC by 8 and each receiver's REC by 1 and
// is retransmitted; successes count them down. Crossing 96, 128 and 256 moves an endpoint to
// error-warning, error-passive and bus-off, and each change reaches that endpoint as a Linux-style
// controller error frame (if its error mask asks). A bus-off endpoint drops its TX queue, refuses
// to send and hears nothing until it restarts (RestartEndpoint, or automatically after
// bus_off_restart_ns, like Linux's restart-ms). Not modelled: ACK errors (a frame with nobody
// else on the bus still succeeds), overload frames, and the 8-bit suspend of error-passive senders.
//
// Threading: endpoints and the bus are single-threaded by design (the runner drives everything
// in lockstep), so there are no mutexes. Use them from one thread only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rig/bus_fault_injection.h"
#include "rig/can_bus.h"

namespace hilrig::rig {

struct EmulatedBusConfig {
  std::int64_t nominal_bitrate_bps = 1'000'000;
  std::int64_t data_bitrate_bps = 1'000'000;
  std::size_t rx_queue_capacity = 4096;  // per endpoint; excess frames are dropped and counted
  bool receive_own_frames = false;       // initial SetReceiveOwnFrames of every endpoint
  // Per endpoint: frames accepted by Send that have not started on the wire. A full queue makes
  // Send fail, like ENOBUFS from a full qdisc.
  std::size_t tx_queue_capacity = 64;
  BusFaultConfig faults{};
  // 0: a bus-off endpoint waits for RestartEndpoint. Otherwise it restarts this long after going
  // bus-off, but never sooner than the 128 x 11 recessive bits the standard requires.
  std::int64_t bus_off_restart_ns = 0;
};

// Queueing latency is the time from Send to the start of the successful transmission: waiting
// for frames ahead in the own queue, for the frame on the wire, for lost arbitrations and for
// retransmissions.
struct IdQueueingStats {
  std::uint32_t id = 0;
  bool extended = false;
  std::uint64_t frames = 0;
  std::int64_t max_queueing_ns = 0;
  std::int64_t total_queueing_ns = 0;

  std::int64_t mean_queueing_ns() const;
};

// Counts every occupation of the wire: delivered, dropped and corrupted frames and error frames.
// busy_ns is the sum of their durations, so bus load = busy_ns / elapsed time.
struct EmulatedBusStats {
  std::uint64_t frames = 0;
  std::int64_t busy_ns = 0;
  std::uint64_t frames_dropped = 0;    // injected drops
  std::uint64_t frames_corrupted = 0;  // injected corruptions, each followed by a retransmission
  std::vector<IdQueueingStats> queueing_by_id;  // sorted by (extended, id)

  double LoadOver(std::int64_t elapsed_ns) const;
  // Null if no frame with that id has been transmitted.
  const IdQueueingStats* QueueingFor(std::uint32_t id, bool extended = false) const;
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
  // detaches it, frames still queued for or by it are discarded. Name is for diagnostics and
  // for the fault controls below.
  std::unique_ptr<CanBus> Connect(std::string name);

  // Decides the wire up to now_ns without sending or receiving, e.g. before reading stats.
  void AdvanceTo(std::int64_t now_ns);
  // Stats of the wire as decided so far (frames still waiting at the latest time are not in).
  EmulatedBusStats stats() const;

  // Fault controls. They act at now_ns and fail on a frame that is not an error frame or a name
  // no endpoint has.
  // An error frame on the wire, ahead of any waiting frame, to every endpoint whose mask wants it.
  Result<void> InjectErrorFrame(const CanFrame& error_frame, std::int64_t now_ns);
  // The endpoint's TEC jumps past 255, as after a run of transmit errors.
  Result<void> ForceBusOff(std::string_view endpoint_name, std::int64_t now_ns);
  // Brings a bus-off endpoint back, error-active with cleared counters (ip link ... restart).
  Result<void> RestartEndpoint(std::string_view endpoint_name, std::int64_t now_ns);

 private:
  // Behind a pointer so endpoints keep a stable address to it when the bus is moved.
  std::unique_ptr<EmulatedMedium> medium_;
};

}  // namespace hilrig::rig
