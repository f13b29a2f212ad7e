// CanBus is the seam every CAN backend implements (emulated medium, SocketCAN, gs_usb, loopback
// UDP), so the runner and device emulators cannot tell a simulated bus from real hardware. Time is
// always passed in rather than read, which keeps emulated backends deterministic. Every backend
// must pass the same shared test suite (tests/rig/can_bus_conformance.h).
//
// Receive semantics follow Linux's CAN_RAW socket so that a SocketCAN backend maps one to one:
// id/mask filters with the EFF and RTR flag bits, inverted filters, an error-class mask for error
// frames, and an opt-in echo of the endpoint's own frames (CAN_RAW_RECV_OWN_MSGS). Bus state and
// error events travel as Linux-style error frames (class bits in the id, details in the data), so
// one decoder serves every backend; the class and detail bits are named below.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "rig/can_frame.h"
#include "rig/result.h"

namespace hilrig::rig {

// Flag bits of a Linux canid_t (linux/can.h), for translating filters to and from the kernel.
inline constexpr std::uint32_t kCanEffFlag = 0x80000000U;
inline constexpr std::uint32_t kCanRtrFlag = 0x40000000U;
inline constexpr std::uint32_t kCanErrFlag = 0x20000000U;    // in a frame's can_id
inline constexpr std::uint32_t kCanInvFilter = 0x20000000U;  // in a filter's can_id
inline constexpr std::uint32_t kCanSffMask = 0x000007FFU;
inline constexpr std::uint32_t kCanEffMask = 0x1FFFFFFFU;
inline constexpr std::uint32_t kCanErrMask = 0x1FFFFFFFU;  // every error class

// Error frame classes and details as in linux/can/error.h. Class bits go in CanFrame::id.
namespace can_error {
inline constexpr std::uint32_t kTxTimeout = 0x001;
inline constexpr std::uint32_t kLostArbitration = 0x002;
inline constexpr std::uint32_t kController = 0x004;  // details in data[1]
inline constexpr std::uint32_t kProtocol = 0x008;    // type in data[2], location in data[3]
inline constexpr std::uint32_t kTransceiver = 0x010;
inline constexpr std::uint32_t kNoAck = 0x020;
inline constexpr std::uint32_t kBusOff = 0x040;
inline constexpr std::uint32_t kBusError = 0x080;
inline constexpr std::uint32_t kRestarted = 0x100;
inline constexpr std::uint32_t kCounters = 0x200;  // TEC in data[6], REC in data[7]

// data[1] of a kController frame.
inline constexpr std::uint8_t kCtrlRxOverflow = 0x01;
inline constexpr std::uint8_t kCtrlTxOverflow = 0x02;
inline constexpr std::uint8_t kCtrlRxWarning = 0x04;
inline constexpr std::uint8_t kCtrlTxWarning = 0x08;
inline constexpr std::uint8_t kCtrlRxPassive = 0x10;
inline constexpr std::uint8_t kCtrlTxPassive = 0x20;
inline constexpr std::uint8_t kCtrlActive = 0x40;

// data[2] (type) and data[3] (location) of a kProtocol frame.
inline constexpr std::uint8_t kProtTypeUnspecified = 0x00;
inline constexpr std::uint8_t kProtTypeTx = 0x80;  // the error happened while transmitting
inline constexpr std::uint8_t kProtLocCrcSequence = 0x08;
}  // namespace can_error

// A frame matches a filter if ((frame.id ^ id) & mask) == 0 and, when match_extended is set,
// frame.extended == extended, and, when match_remote is set, frame.remote == remote; `inverted`
// negates the whole match. This is exactly Linux's can_filter with CAN_EFF_FLAG / CAN_RTR_FLAG in
// can_mask and CAN_INV_FILTER in can_id (see ToKernelFilter). The defaults make it a plain
// {id, mask} filter: EFF compared, RTR ignored.
//
// Like SocketCAN, a frame passes if any filter matches (and is delivered once). Unlike a raw
// socket, an empty list accepts everything (the kernel would accept nothing; a SocketCAN backend
// installs {0, 0} instead). Error frames are not subject to filters: an endpoint delivers them
// per its error-class mask (Linux's CAN_RAW_ERR_FILTER).
struct CanFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;
  bool extended = false;
  bool inverted = false;
  bool match_extended = true;  // CAN_EFF_FLAG set in the kernel can_mask
  bool remote = false;
  bool match_remote = false;  // CAN_RTR_FLAG set in the kernel can_mask
};

// The kernel's struct can_filter, flag bits included.
struct KernelCanFilter {
  std::uint32_t can_id = 0;
  std::uint32_t can_mask = 0;
};

KernelCanFilter ToKernelFilter(const CanFilter& filter);
CanFilter FromKernelFilter(const KernelCanFilter& filter);
bool FilterAccepts(std::span<const CanFilter> filters, const CanFrame& frame);

enum class BusState { kErrorActive, kErrorWarning, kErrorPassive, kBusOff };

struct BusCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t frames_dropped_rx_overflow = 0;
  std::uint64_t send_failures = 0;
  // Input that could not be a frame (e.g. a bad UDP datagram): counted and dropped, never raised.
  std::uint64_t frames_dropped_malformed = 0;
  // Frames from a sender that is not a member of the bus (a UDP datagram from a port outside it):
  // counted and dropped, so that no other process on the host can inject sensor data.
  std::uint64_t frames_dropped_foreign = 0;
  // Frames accepted by Send but discarded before transmission (the controller went bus-off).
  std::uint64_t frames_dropped_tx = 0;
  // The controller's error counters (TEC, REC) where the backend has them; 0 otherwise.
  std::uint32_t transmit_error_count = 0;
  std::uint32_t receive_error_count = 0;
};

// What error frames say, typed. Every backend receives Linux-style error frames (see above), so
// this one decoder serves SocketCAN and gs_usb alike.
enum class BusEventKind {
  kBusOff,            // controller left the bus (CAN_ERR_BUSOFF)
  kRestarted,         // controller restarted after bus-off (CAN_ERR_RESTARTED)
  kErrorWarning,      // an error counter reached 96 (CAN_ERR_CRTL_{RX,TX}_WARNING)
  kErrorPassive,      // an error counter reached 128 (CAN_ERR_CRTL_{RX,TX}_PASSIVE)
  kErrorActive,       // counters back under 96 (CAN_ERR_CRTL_ACTIVE)
  kAckError,          // a sent frame was not acknowledged: nobody else on the bus (CAN_ERR_ACK)
  kRxOverflow,        // the controller's receive buffer overflowed (CAN_ERR_CRTL_RX_OVERFLOW)
  kTxOverflow,        // the controller's transmit buffer overflowed (CAN_ERR_CRTL_TX_OVERFLOW)
  kTxTimeout,         // the driver gave up on a frame (CAN_ERR_TX_TIMEOUT)
  kLostArbitration,   // (CAN_ERR_LOSTARB); data[0] holds the bit position
  kProtocolError,     // bit, form, stuff, CRC... (CAN_ERR_PROT); details in the raw frame
  kBusError,          // unspecified bus error (CAN_ERR_BUSERROR)
  kTransceiverError,  // wiring faults the transceiver reports (CAN_ERR_TRX)
  kSocketOverflow,    // the kernel dropped frames because this socket was not drained in time
};

const char* BusEventKindName(BusEventKind kind);

struct BusEvent {
  BusEventKind kind = BusEventKind::kBusError;
  std::int64_t time_ns = 0;
  // For warning and passive: whether the TX (true) or RX (false) counter crossed the level. When
  // both did, two events are emitted.
  bool tx = false;
  // Error counters when the frame carries them (CAN_ERR_CNT), else 0 and has_counters false.
  bool has_counters = false;
  std::uint8_t tx_error_count = 0;
  std::uint8_t rx_error_count = 0;
  // kSocketOverflow: frames lost since the previous event.
  std::uint32_t dropped_frames = 0;
  // The error frame the event came from, so nothing the kernel said is lost.
  CanFrame frame;
};

// Decodes one Linux error frame into events, in a fixed order (bus-off and state changes first).
// Pure: exposed so the decoding is tested on any kernel. A non-error frame yields nothing.
std::vector<BusEvent> DecodeErrorFrame(const CanFrame& frame, std::int64_t time_ns);

// Applies decoded events to a bus state, as the controller's state machine would.
BusState NextBusState(BusState state, const BusEvent& event);

// The state one error frame's events announce, if any. A frame can announce several (bus-off with
// passive, say); the most severe wins, as in the Linux driver's state update. For a backend that
// applies each frame as a whole rather than event by event.
std::optional<BusState> AnnouncedBusState(std::span<const BusEvent> events);

class CanBus {
 public:
  virtual ~CanBus() = default;
  // Queues a frame for transmission at now_ns. Fails (as a value) on an invalid frame, bus-off or
  // a full TX queue.
  virtual Result<void> Send(const CanFrame& frame, std::int64_t now_ns) = 0;
  // Appends to `out` every frame that has finished arriving at or before now_ns and passes the
  // filters, oldest first; returns how many were appended. Echoes of own frames carry tx_echo.
  virtual std::size_t Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) = 0;
  virtual void SetFilters(std::span<const CanFilter> filters) = 0;
  // All error classes or none; SetErrorFrameMask selects classes.
  virtual void SetReceiveErrorFrames(bool enabled) = 0;
  // Error frames whose class bits intersect class_mask are delivered (CAN_RAW_ERR_FILTER).
  // Backends that cannot select classes fall back to all-or-none.
  virtual void SetErrorFrameMask(std::uint32_t class_mask) {
    SetReceiveErrorFrames(class_mask != 0);
  }
  // Whether this endpoint also receives its own frames once they are on the bus, marked tx_echo
  // (CAN_RAW_RECV_OWN_MSGS). Off by default; a backend that cannot echo refuses to turn it on.
  virtual Result<void> SetReceiveOwnFrames(bool enabled) {
    if (!enabled) return {};
    return MakeError("this CAN backend cannot echo sent frames");
  }
  virtual BusState state() const = 0;
  virtual BusCounters counters() const = 0;
};

}  // namespace hilrig::rig
