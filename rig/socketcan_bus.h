// SocketCanBus puts a Linux SocketCAN interface (can0, vcan0, a gs_usb adapter bound by the kernel
// driver) behind the CanBus seam, so a bench run talks to real hardware through the same calls an
// emulated run makes. It is a raw CAN_RAW socket held by Boost.Asio: the socket is non-blocking,
// Receive drains what the kernel has queued, and WaitReadable lets a bench loop sleep until a frame
// arrives instead of spinning.
//
// What the kernel gives us and how it maps onto the seam:
// - CAN FD: CAN_RAW_FD_FRAMES is always enabled, so classic and FD frames both arrive; sending an
//   FD frame on an interface whose MTU is classic-only fails as a value, not as EINVAL later.
// - Filters: CanFilter is Linux's can_filter already (ToKernelFilter in can_bus.h). An empty list
//   becomes the accept-all filter, because the kernel reads "no filters" as "receive nothing".
//   Filtering happens in the kernel, so unwanted traffic never reaches user space.
// - Timestamps: every frame is stamped with the kernel's receive time (SO_TIMESTAMPNS, read through
//   recvmsg), in CLOCK_REALTIME nanoseconds since the epoch: the same time base candump -l logs
//   use. It is not the caller's Clock domain; this class never reads a clock itself.
// - Error frames: decoded into typed BusEvents (bus-off, warning, passive, ACK error, overflows)
//   and used to track state() and the error counters. The state-changing classes (bus-off,
//   controller, restarted, TX timeout) are always subscribed in the kernel's CAN_RAW_ERR_FILTER so
//   state() stays true even when the caller wants no error frames; they reach Receive only if the
//   caller's error_frame_mask selects them. The classes that can flood a sick bus (bus errors,
//   protocol, ACK) are subscribed only when the caller's mask asks for them. After bus-off, Send
//   refuses until a restarted or error-active frame arrives (the kernel sends one after
//   restart-ms or `ip link set canX type can restart`); a down/up restart sends none, so reopen.
// - Error frames can also be sent, which on vcan injects faults for tests and bench rehearsals.
// - Own frames: with receive_own_frames (CAN_RAW_RECV_OWN_MSGS) a sent frame comes back marked
//   tx_echo (MSG_CONFIRM) and stamped with the time it left, which is how a bench run confirms
//   transmission.
// - Full TX queue: the kernel answers ENOBUFS when the interface queue is full. Send retries a
//   bounded number of times with a short growing pause, counts the retries, and then fails.
//
// A kernel without AF_CAN (this CI machine's, for one) makes OpenSocketCan return an error that
// says so; the vm test runs the same code under QEMU on a kernel that has it.
//
// Threading: one thread per bus, like every CanBus.
#pragma once

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rig/can_bus.h"
#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// The bounded retry Send applies to a full TX queue, kept apart so it is tested without a kernel.
// `attempt` makes one send and returns 0 or an errno value; ENOBUFS and EAGAIN (queue full) are
// retried up to max_retries times with `pause(pause_ns)` between, the pause doubling each time;
// EINTR is retried without counting; any other errno ends at once.
struct SendRetryOutcome {
  int error_number = 0;  // 0 when the frame was sent
  int retries = 0;       // queue-full retries made
};
// A template on its callables, so Send's lambdas are called directly and nothing allocates.
template <typename Attempt, typename Pause>
SendRetryOutcome SendWithRetry(Attempt&& attempt, int max_retries, std::int64_t first_pause_ns,
                               Pause&& pause) {
  SendRetryOutcome outcome;
  std::int64_t pause_ns = first_pause_ns;
  for (;;) {
    outcome.error_number = attempt();
    if (outcome.error_number == EINTR) continue;
    const bool queue_full = outcome.error_number == ENOBUFS || outcome.error_number == EAGAIN;
    if (!queue_full || outcome.retries >= max_retries) return outcome;
    ++outcome.retries;
    pause(pause_ns);
    pause_ns *= 2;
  }
}

struct SocketCanOptions {
  std::vector<CanFilter> filters;  // empty: accept every frame
  // Error classes (can_error::k*) delivered to Receive; 0 none, kCanErrMask all. Events and
  // state are kept whatever the mask.
  std::uint32_t error_frame_mask = 0;
  bool receive_own_frames = false;  // CAN_RAW_RECV_OWN_MSGS: see our own frames come back
  bool loopback = true;             // CAN_RAW_LOOPBACK: other sockets on this host see ours
  int max_send_retries = 8;         // retries on ENOBUFS/EAGAIN before Send fails
  std::int64_t first_retry_pause_ns = 50'000;  // doubled per retry: 8 retries wait ~13 ms in all
  std::size_t max_buffered_events = 4096;      // oldest events are dropped past this
  int receive_buffer_bytes = 0;                // SO_RCVBUF; 0 keeps the kernel default
};

// SocketCAN-specific counters beyond BusCounters.
struct SocketCanStats {
  std::uint64_t send_retries = 0;      // ENOBUFS/EAGAIN retries that preceded a send or failure
  std::uint64_t error_frames = 0;      // error frames read from the socket
  std::uint64_t events_discarded = 0;  // events dropped because nobody took them
};

class SocketCanBus final : public CanBus {
 public:
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  // Fails on an invalid frame, an FD frame on a classic interface, a bus-off controller, the
  // interface being down, or a TX queue that stays full through every retry.
  Result<void> Send(const CanFrame& frame, std::int64_t now_ns) override;
  // Drains every frame the kernel has queued, without blocking. now_ns is only the stamp of last
  // resort (should a frame ever arrive without a kernel timestamp): a frame in the socket queue
  // has already arrived, so nothing is held back.
  std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) override;
  void SetFilters(std::span<const CanFilter> filters) override;
  void SetReceiveErrorFrames(bool enabled) override;
  void SetErrorFrameMask(std::uint32_t class_mask) override;
  Result<void> SetReceiveOwnFrames(bool enabled) override;
  BusState state() const override;
  BusCounters counters() const override;

  // Blocks until a frame (or error frame) can be read, at most timeout_ns. True if readable.
  // For bench loops and tests that wait on real traffic; emulated runs never need it.
  bool WaitReadable(std::int64_t timeout_ns);

  // Events decoded since the last call, oldest first. Events are decoded while Receive drains
  // the socket, so call Receive first.
  std::vector<BusEvent> TakeEvents();
  const std::deque<BusEvent>& events() const;

  SocketCanStats stats() const;
  const std::string& interface_name() const;
  bool fd_capable() const;  // the interface MTU admits CAN FD frames

 private:
  struct Impl;
  explicit SocketCanBus(std::unique_ptr<Impl> impl);
  friend Result<std::unique_ptr<SocketCanBus>> OpenSocketCan(const std::string& interface,
                                                             const SocketCanOptions& options);

  std::unique_ptr<Impl> impl_;
};

// Opens a CAN_RAW socket bound to `interface`. Errors say which step failed and why: no AF_CAN in
// this kernel, no such interface, not a CAN interface, or an option the kernel refused.
// Returns the concrete type so events and stats stay reachable; it converts to
// std::unique_ptr<CanBus> where only the seam is wanted.
Result<std::unique_ptr<SocketCanBus>> OpenSocketCan(const std::string& interface,
                                                    const SocketCanOptions& options = {});

}  // namespace hilrig::rig
