#include "rig/socketcan_bus.h"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>

#include <algorithm>
#include <boost/asio/basic_raw_socket.hpp>
#include <boost/asio/generic/raw_protocol.hpp>
#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <iterator>
#include <thread>
#include <utility>

#include "rig/check.h"

namespace hilrig::rig {
namespace {

using RawProtocol = boost::asio::generic::raw_protocol;
using RawSocket = boost::asio::basic_raw_socket<RawProtocol>;

// The shared error-frame decoder (can_bus.h) names linux/can/error.h's bits itself.
static_assert(can_error::kBusOff == CAN_ERR_BUSOFF && can_error::kRestarted == CAN_ERR_RESTARTED &&
              can_error::kController == CAN_ERR_CRTL && can_error::kNoAck == CAN_ERR_ACK &&
              can_error::kTxTimeout == CAN_ERR_TX_TIMEOUT &&
              can_error::kLostArbitration == CAN_ERR_LOSTARB &&
              can_error::kProtocol == CAN_ERR_PROT && can_error::kBusError == CAN_ERR_BUSERROR &&
              can_error::kTransceiver == CAN_ERR_TRX && can_error::kCounters == CAN_ERR_CNT);
static_assert(can_error::kCtrlRxOverflow == CAN_ERR_CRTL_RX_OVERFLOW &&
              can_error::kCtrlTxOverflow == CAN_ERR_CRTL_TX_OVERFLOW &&
              can_error::kCtrlRxWarning == CAN_ERR_CRTL_RX_WARNING &&
              can_error::kCtrlTxWarning == CAN_ERR_CRTL_TX_WARNING &&
              can_error::kCtrlRxPassive == CAN_ERR_CRTL_RX_PASSIVE &&
              can_error::kCtrlTxPassive == CAN_ERR_CRTL_TX_PASSIVE &&
              can_error::kCtrlActive == CAN_ERR_CRTL_ACTIVE &&
              can_error::kProtTypeTx == CAN_ERR_PROT_TX);
static_assert(kCanErrFlag == CAN_ERR_FLAG && kCanEffFlag == CAN_EFF_FLAG);

// Error classes whose frames change the controller state: always subscribed so state() is right.
constexpr can_err_mask_t kStateErrorClasses =
    CAN_ERR_BUSOFF | CAN_ERR_CRTL | CAN_ERR_RESTARTED | CAN_ERR_TX_TIMEOUT;

std::string ErrnoText(int error_number) { return std::strerror(error_number); }

std::vector<can_filter> ToKernelFilters(std::span<const CanFilter> filters) {
  std::vector<can_filter> kernel;
  if (filters.empty()) {
    // The kernel reads zero filters as "receive nothing"; CanBus reads it as "receive all".
    kernel.push_back(can_filter{.can_id = 0, .can_mask = 0});
    return kernel;
  }
  kernel.reserve(filters.size());
  for (const CanFilter& filter : filters) {
    const KernelCanFilter out = ToKernelFilter(filter);
    kernel.push_back(can_filter{.can_id = out.can_id, .can_mask = out.can_mask});
  }
  return kernel;
}

canfd_frame ToKernelFrame(const CanFrame& frame) {
  canfd_frame out{};
  if (frame.error) {
    out.can_id = CAN_ERR_FLAG | (frame.id & CAN_ERR_MASK);
  } else {
    out.can_id =
        frame.id | (frame.extended ? CAN_EFF_FLAG : 0u) | (frame.remote ? CAN_RTR_FLAG : 0u);
  }
  out.len = frame.length;
  if (frame.fd) {
    out.flags = CANFD_FDF | (frame.bitrate_switch ? CANFD_BRS : 0) |
                (frame.error_state_indicator ? CANFD_ESI : 0);
  }
  if (!frame.remote) std::memcpy(out.data, frame.data.data(), frame.length);
  return out;
}

CanFrame FromKernelFrame(const canfd_frame& in, bool fd) {
  CanFrame frame;
  frame.fd = fd;
  frame.length = in.len;
  if (in.can_id & CAN_ERR_FLAG) {
    frame.error = true;
    frame.id = in.can_id & CAN_ERR_MASK;
  } else {
    frame.extended = (in.can_id & CAN_EFF_FLAG) != 0;
    frame.remote = !fd && (in.can_id & CAN_RTR_FLAG) != 0;
    frame.id = in.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  }
  if (fd) {
    frame.bitrate_switch = (in.flags & CANFD_BRS) != 0;
    frame.error_state_indicator = (in.flags & CANFD_ESI) != 0;
  }
  if (!frame.remote) {
    const std::size_t max = fd ? CanFrame::kMaxFdPayload : CanFrame::kMaxClassicPayload;
    std::memcpy(frame.data.data(), in.data, std::min<std::size_t>(in.len, max));
  }
  return frame;
}

Result<void> SetSocketOption(int fd, int level, int name, const void* value, socklen_t size,
                             const char* what) {
  if (::setsockopt(fd, level, name, value, size) != 0) {
    return MakeError(std::string("SocketCAN: setting ") + what + " failed: " + ErrnoText(errno));
  }
  return {};
}

}  // namespace

struct SocketCanBus::Impl {
  Impl() : socket(io) {}

  boost::asio::io_context io;
  RawSocket socket;
  std::string interface_name;
  SocketCanOptions options;
  bool fd_capable = false;
  BusState state = BusState::kErrorActive;
  BusCounters counters;
  SocketCanStats stats;
  std::deque<BusEvent> events;        // drop-oldest at max_buffered_events
  std::uint32_t last_drop_count = 0;  // SO_RXQ_OVFL is cumulative per socket

  int fd() { return socket.native_handle(); }

  Result<void> ApplyFilters(std::span<const CanFilter> filters) {
    if (filters.size() > CAN_RAW_FILTER_MAX) {
      return MakeError("SocketCAN: " + std::to_string(filters.size()) +
                       " filters, the kernel takes at most " + std::to_string(CAN_RAW_FILTER_MAX));
    }
    const std::vector<can_filter> kernel = ToKernelFilters(filters);
    return SetSocketOption(fd(), SOL_CAN_RAW, CAN_RAW_FILTER, kernel.data(),
                           static_cast<socklen_t>(kernel.size() * sizeof(can_filter)),
                           "CAN_RAW_FILTER");
  }

  Result<void> ApplyErrorMask(std::uint32_t delivered_classes) {
    const can_err_mask_t mask = (delivered_classes & CAN_ERR_MASK) | kStateErrorClasses;
    return SetSocketOption(fd(), SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof(mask),
                           "CAN_RAW_ERR_FILTER");
  }

  void AddEvent(BusEvent event) {
    state = NextBusState(state, event);
    if (event.has_counters) {
      counters.transmit_error_count = event.tx_error_count;
      counters.receive_error_count = event.rx_error_count;
    }
    if (events.size() >= options.max_buffered_events) {
      events.pop_front();
      ++stats.events_discarded;
    }
    events.push_back(std::move(event));
  }

  // The kernel's cumulative count of frames it could not queue for this socket.
  void NoteDropCount(std::uint32_t drop_count, std::int64_t time_ns) {
    const std::uint32_t dropped = drop_count - last_drop_count;  // wraps like the kernel's
    if (dropped == 0) return;
    last_drop_count = drop_count;
    counters.frames_dropped_rx_overflow += dropped;
    BusEvent event;
    event.kind = BusEventKind::kSocketOverflow;
    event.time_ns = time_ns;
    event.dropped_frames = dropped;
    AddEvent(std::move(event));
  }
};

SocketCanBus::SocketCanBus(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SocketCanBus::~SocketCanBus() = default;

Result<std::unique_ptr<SocketCanBus>> OpenSocketCan(const std::string& interface,
                                                    const SocketCanOptions& options) {
  auto impl = std::make_unique<SocketCanBus::Impl>();
  impl->interface_name = interface;
  impl->options = options;
  if (interface.empty() || interface.size() >= IFNAMSIZ) {
    return MakeError("SocketCAN: bad interface name '" + interface + "'");
  }

  boost::system::error_code ec;
  impl->socket.open(RawProtocol(PF_CAN, CAN_RAW), ec);
  if (ec) {
    if (ec.value() == EAFNOSUPPORT || ec.value() == EPROTONOSUPPORT) {
      return MakeError("SocketCAN: no AF_CAN in this kernel (socket(PF_CAN, SOCK_RAW, CAN_RAW): " +
                       ec.message() + "); load can and can-raw, or run the vm test");
    }
    return MakeError("SocketCAN: socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: " + ec.message());
  }
  const int fd = impl->fd();

  ifreq request{};
  std::memcpy(request.ifr_name, interface.c_str(), interface.size() + 1);
  if (::ioctl(fd, SIOCGIFINDEX, &request) != 0) {
    return MakeError("SocketCAN: no interface named '" + interface + "': " + ErrnoText(errno));
  }
  const int interface_index = request.ifr_ifindex;
  if (::ioctl(fd, SIOCGIFMTU, &request) != 0) {
    return MakeError("SocketCAN: cannot read the MTU of '" + interface + "': " + ErrnoText(errno));
  }
  impl->fd_capable = request.ifr_mtu >= static_cast<int>(CANFD_MTU);

  const int on = 1;
  const int recv_own = options.receive_own_frames ? 1 : 0;
  const int loopback = options.loopback ? 1 : 0;
  // Each option is set only if the ones before it were accepted; the first refusal is the error.
  Result<void> configured =
      SetSocketOption(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof(on), "CAN_RAW_FD_FRAMES");
  if (configured) {
    configured = SetSocketOption(fd, SOL_CAN_RAW, CAN_RAW_LOOPBACK, &loopback, sizeof(loopback),
                                 "CAN_RAW_LOOPBACK");
  }
  if (configured) {
    configured = SetSocketOption(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &recv_own,
                                 sizeof(recv_own), "CAN_RAW_RECV_OWN_MSGS");
  }
  if (configured) {
    configured = SetSocketOption(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on), "SO_TIMESTAMPNS");
  }
  if (configured) {
    configured = SetSocketOption(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on), "SO_RXQ_OVFL");
  }
  if (configured) configured = impl->ApplyFilters(options.filters);
  if (configured) configured = impl->ApplyErrorMask(options.error_frame_mask);
  if (configured && options.receive_buffer_bytes > 0) {
    configured = SetSocketOption(fd, SOL_SOCKET, SO_RCVBUF, &options.receive_buffer_bytes,
                                 sizeof(options.receive_buffer_bytes), "SO_RCVBUF");
  }
  if (!configured) return configured.error();

  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = interface_index;
  impl->socket.bind(RawProtocol::endpoint(&address, sizeof(address), CAN_RAW), ec);
  if (ec) {
    return MakeError("SocketCAN: cannot bind to '" + interface +
                     "' (is it a CAN interface?): " + ec.message());
  }
  // Receive must never block, and Send handles a full queue itself.
  impl->socket.non_blocking(true, ec);
  if (ec) return MakeError("SocketCAN: cannot make the socket non-blocking: " + ec.message());

  return std::unique_ptr<SocketCanBus>(new SocketCanBus(std::move(impl)));
}

Result<void> SocketCanBus::Send(const CanFrame& frame, std::int64_t /*now_ns*/) {
  Impl& impl = *impl_;
  auto fail = [&impl](std::string message) -> Result<void> {
    ++impl.counters.send_failures;
    return MakeError("SocketCAN " + impl.interface_name + ": " + std::move(message));
  };
  if (Result<void> valid = ValidateFrame(frame); !valid) return fail(valid.error().message);
  if (frame.fd && !impl.fd_capable) return fail("CAN FD frame on an interface with a classic MTU");
  if (impl.state == BusState::kBusOff) return fail("controller is bus-off");

  const canfd_frame kernel = ToKernelFrame(frame);
  const std::size_t size = frame.fd ? CANFD_MTU : CAN_MTU;
  const int fd = impl.fd();
  const SendRetryOutcome outcome = SendWithRetry(
      [fd, &kernel, size] {
        const ssize_t sent = ::send(fd, &kernel, size, MSG_DONTWAIT);
        if (sent == static_cast<ssize_t>(size)) return 0;
        return sent < 0 ? errno : EIO;  // a short write of a CAN frame: should never happen
      },
      impl.options.max_send_retries, impl.options.first_retry_pause_ns,
      // The queue drains at wire speed; pausing is the only way to give it time, and the pauses
      // are bounded (first_retry_pause_ns * 2^max_send_retries in all).
      [](std::int64_t pause_ns) {
        std::this_thread::sleep_for(std::chrono::nanoseconds(pause_ns));
      });
  impl.stats.send_retries += static_cast<std::uint64_t>(outcome.retries);
  switch (outcome.error_number) {
    case 0:
      ++impl.counters.frames_sent;
      return {};
    case ENOBUFS:
    case EAGAIN:
      return fail("TX queue still full (" + ErrnoText(outcome.error_number) + ") after " +
                  std::to_string(outcome.retries) +
                  " retries; the bus is not taking frames (no ACK? txqueuelen too small?)");
    case ENETDOWN:
      return fail("interface is down (or the controller bus-off)");
    default:
      return fail("send failed: " + ErrnoText(outcome.error_number));
  }
}

std::size_t SocketCanBus::Receive(std::int64_t now_ns, std::vector<TimedCanFrame>& out) {
  Impl& impl = *impl_;
  std::size_t appended = 0;
  for (;;) {
    canfd_frame kernel{};
    iovec buffer{&kernel, sizeof(kernel)};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr message{};
    message.msg_iov = &buffer;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof(control);
    const ssize_t size = ::recvmsg(impl.fd(), &message, MSG_DONTWAIT);
    if (size < 0) {
      if (errno == EINTR) continue;
      // EAGAIN: drained. Anything else (ENETDOWN when the interface goes down) also means
      // nothing more to read now; the next Send reports the condition as a value.
      break;
    }
    std::int64_t time_ns = now_ns;
    for (cmsghdr* header = CMSG_FIRSTHDR(&message); header != nullptr;
         header = CMSG_NXTHDR(&message, header)) {
      if (header->cmsg_level != SOL_SOCKET) continue;
      if (header->cmsg_type == SCM_TIMESTAMPNS) {
        timespec stamp;
        std::memcpy(&stamp, CMSG_DATA(header), sizeof(stamp));
        time_ns = static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000'000 + stamp.tv_nsec;
      } else if (header->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t drop_count;
        std::memcpy(&drop_count, CMSG_DATA(header), sizeof(drop_count));
        impl.NoteDropCount(drop_count, time_ns);
      }
    }
    if (size != static_cast<ssize_t>(CAN_MTU) && size != static_cast<ssize_t>(CANFD_MTU)) {
      // Not a CAN or CAN FD frame (CAN XL on a newer kernel): not ours to interpret.
      ++impl.counters.frames_dropped_malformed;
      continue;
    }
    const CanFrame frame = FromKernelFrame(kernel, size == static_cast<ssize_t>(CANFD_MTU));
    if (!ValidateFrame(frame)) {
      ++impl.counters.frames_dropped_malformed;
      continue;
    }
    if (frame.error) {
      ++impl.stats.error_frames;
      for (BusEvent& event : DecodeErrorFrame(frame, time_ns)) impl.AddEvent(std::move(event));
      // Subscribed for state tracking only, unless the caller's mask selects the class too.
      if ((frame.id & impl.options.error_frame_mask) == 0) continue;
    }
    // MSG_CONFIRM marks a frame this very socket sent (CAN_RAW_RECV_OWN_MSGS).
    const bool tx_echo = (message.msg_flags & MSG_CONFIRM) != 0;
    out.push_back(TimedCanFrame{.frame = frame, .time_ns = time_ns, .tx_echo = tx_echo});
    ++impl.counters.frames_received;
    ++appended;
  }
  return appended;
}

void SocketCanBus::SetFilters(std::span<const CanFilter> filters) {
  Result<void> applied = impl_->ApplyFilters(filters);
  HILRIG_CHECK(applied.ok(), applied.error().message);
}

void SocketCanBus::SetReceiveErrorFrames(bool enabled) {
  SetErrorFrameMask(enabled ? static_cast<std::uint32_t>(CAN_ERR_MASK) : 0u);
}

void SocketCanBus::SetErrorFrameMask(std::uint32_t class_mask) {
  Result<void> applied = impl_->ApplyErrorMask(class_mask);
  HILRIG_CHECK(applied.ok(), applied.error().message);
  impl_->options.error_frame_mask = class_mask & CAN_ERR_MASK;
}

Result<void> SocketCanBus::SetReceiveOwnFrames(bool enabled) {
  const int value = enabled ? 1 : 0;
  return SetSocketOption(impl_->fd(), SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &value, sizeof(value),
                         "CAN_RAW_RECV_OWN_MSGS");
}

BusState SocketCanBus::state() const { return impl_->state; }
BusCounters SocketCanBus::counters() const { return impl_->counters; }

bool SocketCanBus::WaitReadable(std::int64_t timeout_ns) {
  Impl& impl = *impl_;
  bool readable = false;
  impl.socket.async_wait(RawSocket::wait_read,
                         [&readable](const boost::system::error_code& ec) { readable = !ec; });
  impl.io.restart();
  impl.io.run_for(std::chrono::nanoseconds(std::max<std::int64_t>(timeout_ns, 0)));
  if (!impl.io.stopped()) {
    // Timed out with the wait still pending: cancel it and let its handler run before returning,
    // since it refers to this stack frame.
    impl.socket.cancel();
    impl.io.restart();
    impl.io.run();
  }
  return readable;
}

std::vector<BusEvent> SocketCanBus::TakeEvents() {
  std::deque<BusEvent>& events = impl_->events;
  std::vector<BusEvent> taken(std::make_move_iterator(events.begin()),
                              std::make_move_iterator(events.end()));
  events.clear();
  return taken;
}
const std::deque<BusEvent>& SocketCanBus::events() const { return impl_->events; }
SocketCanStats SocketCanBus::stats() const { return impl_->stats; }
const std::string& SocketCanBus::interface_name() const { return impl_->interface_name; }
bool SocketCanBus::fd_capable() const { return impl_->fd_capable; }

}  // namespace hilrig::rig
