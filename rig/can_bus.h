// CanBus is the seam every CAN backend implements (emulated medium, SocketCAN, gs_usb, loopback
// UDP), so the runner and device emulators cannot tell a simulated bus from real hardware. Time is
// always passed in rather than read, which keeps emulated backends deterministic. Every backend
// must pass the same shared test suite.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// A frame matches a filter if ((frame.id ^ id) & mask) == 0 and frame.extended == extended;
// `inverted` negates that. Like SocketCAN, a frame passes if any filter matches, and an empty
// list accepts everything. Remote frames match like data frames. Error frames are not subject to
// filters: an endpoint delivers them only if receive_error_frames is set (Linux's err_mask).
struct CanFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;
  bool extended = false;
  bool inverted = false;
};

bool FilterAccepts(std::span<const CanFilter> filters, const CanFrame& frame);

enum class BusState { kErrorActive, kErrorWarning, kErrorPassive, kBusOff };

struct BusCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t frames_dropped_rx_overflow = 0;
  std::uint64_t send_failures = 0;
};

class CanBus {
 public:
  virtual ~CanBus() = default;
  // Queues a frame for transmission at now_ns. Fails (as a value) on an invalid frame, bus-off or
  // a full TX queue.
  virtual Result<void> Send(const CanFrame& frame, std::int64_t now_ns) = 0;
  // Appends to `out` every frame that has finished arriving at or before now_ns and passes the
  // filters, oldest first; returns how many were appended.
  virtual std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) = 0;
  virtual void SetFilters(std::span<const CanFilter> filters) = 0;
  virtual void SetReceiveErrorFrames(bool enabled) = 0;
  virtual BusState state() const = 0;
  virtual BusCounters counters() const = 0;
};

}  // namespace hilrig::rig
