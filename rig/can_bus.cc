#include "rig/can_bus.h"

#include <algorithm>
#include <utility>

namespace hilrig::rig {
namespace {

std::uint32_t KernelId(const CanFrame& frame) {
  return frame.id | (frame.extended ? kCanEffFlag : 0) | (frame.remote ? kCanRtrFlag : 0);
}

// The comparison Linux's af_can does after can_rx_register has normalized the filter.
bool Matches(const CanFilter& filter, const CanFrame& frame) {
  const KernelCanFilter kernel = ToKernelFilter(filter);
  std::uint32_t mask = kernel.can_mask;
  // An SFF-only filter compares just the 11 id bits, as af_can's can_rcv_list_find does.
  if ((mask & kCanEffFlag) != 0 && (kernel.can_id & kCanEffFlag) == 0) {
    mask &= kCanSffMask | kCanEffFlag | kCanRtrFlag;
  }
  const std::uint32_t wanted = kernel.can_id & mask;  // the mask never holds CAN_INV_FILTER
  const bool hit = (KernelId(frame) & mask) == wanted;
  return hit != filter.inverted;
}

BusEvent MakeEvent(BusEventKind kind, const CanFrame& frame, std::int64_t time_ns) {
  BusEvent event;
  event.kind = kind;
  event.time_ns = time_ns;
  event.frame = frame;
  if (frame.id & can_error::kCounters) {
    event.has_counters = true;
    event.tx_error_count = frame.data[6];
    event.rx_error_count = frame.data[7];
  }
  return event;
}

}  // namespace

KernelCanFilter ToKernelFilter(const CanFilter& filter) {
  KernelCanFilter kernel{.can_id = filter.id & kCanEffMask, .can_mask = filter.mask & kCanEffMask};
  if (filter.extended) kernel.can_id |= kCanEffFlag;
  if (filter.remote) kernel.can_id |= kCanRtrFlag;
  if (filter.inverted) kernel.can_id |= kCanInvFilter;
  if (filter.match_extended) kernel.can_mask |= kCanEffFlag;
  if (filter.match_remote) kernel.can_mask |= kCanRtrFlag;
  return kernel;
}

CanFilter FromKernelFilter(const KernelCanFilter& kernel) {
  return CanFilter{.id = kernel.can_id & kCanEffMask,
                   .mask = kernel.can_mask & kCanEffMask,
                   .extended = (kernel.can_id & kCanEffFlag) != 0,
                   .inverted = (kernel.can_id & kCanInvFilter) != 0,
                   .match_extended = (kernel.can_mask & kCanEffFlag) != 0,
                   .remote = (kernel.can_id & kCanRtrFlag) != 0,
                   .match_remote = (kernel.can_mask & kCanRtrFlag) != 0};
}

bool FilterAccepts(std::span<const CanFilter> filters, const CanFrame& frame) {
  if (filters.empty()) return true;
  return std::any_of(filters.begin(), filters.end(),
                     [&frame](const CanFilter& filter) { return Matches(filter, frame); });
}

const char* BusEventKindName(BusEventKind kind) {
  switch (kind) {
    case BusEventKind::kBusOff:
      return "bus-off";
    case BusEventKind::kRestarted:
      return "restarted";
    case BusEventKind::kErrorWarning:
      return "error-warning";
    case BusEventKind::kErrorPassive:
      return "error-passive";
    case BusEventKind::kErrorActive:
      return "error-active";
    case BusEventKind::kAckError:
      return "ack-error";
    case BusEventKind::kRxOverflow:
      return "rx-overflow";
    case BusEventKind::kTxOverflow:
      return "tx-overflow";
    case BusEventKind::kTxTimeout:
      return "tx-timeout";
    case BusEventKind::kLostArbitration:
      return "lost-arbitration";
    case BusEventKind::kProtocolError:
      return "protocol-error";
    case BusEventKind::kBusError:
      return "bus-error";
    case BusEventKind::kTransceiverError:
      return "transceiver-error";
    case BusEventKind::kSocketOverflow:
      return "socket-overflow";
  }
  return "unknown";
}

std::vector<BusEvent> DecodeErrorFrame(const CanFrame& frame, std::int64_t time_ns) {
  std::vector<BusEvent> events;
  if (!frame.error) return events;
  const std::uint32_t classes = frame.id;
  const std::uint8_t controller = frame.data[1];
  auto add = [&](BusEventKind kind, bool tx = false) {
    BusEvent event = MakeEvent(kind, frame, time_ns);
    event.tx = tx;
    events.push_back(std::move(event));
  };
  // State changes first, so a reader replaying events in order ends in the right state.
  if (classes & can_error::kBusOff) add(BusEventKind::kBusOff);
  if (classes & can_error::kRestarted) add(BusEventKind::kRestarted);
  if (classes & can_error::kController) {
    if (controller & can_error::kCtrlRxPassive) add(BusEventKind::kErrorPassive, false);
    if (controller & can_error::kCtrlTxPassive) add(BusEventKind::kErrorPassive, true);
    if (controller & can_error::kCtrlRxWarning) add(BusEventKind::kErrorWarning, false);
    if (controller & can_error::kCtrlTxWarning) add(BusEventKind::kErrorWarning, true);
    if (controller & can_error::kCtrlActive) add(BusEventKind::kErrorActive);
    if (controller & can_error::kCtrlRxOverflow) add(BusEventKind::kRxOverflow);
    if (controller & can_error::kCtrlTxOverflow) add(BusEventKind::kTxOverflow, true);
  }
  if (classes & can_error::kNoAck) add(BusEventKind::kAckError, true);
  if (classes & can_error::kTxTimeout) add(BusEventKind::kTxTimeout, true);
  if (classes & can_error::kLostArbitration) add(BusEventKind::kLostArbitration, true);
  if (classes & can_error::kProtocol)
    add(BusEventKind::kProtocolError, (frame.data[2] & can_error::kProtTypeTx));
  if (classes & can_error::kBusError) add(BusEventKind::kBusError);
  if (classes & can_error::kTransceiver) add(BusEventKind::kTransceiverError);
  return events;
}

BusState NextBusState(BusState state, const BusEvent& event) {
  switch (event.kind) {
    case BusEventKind::kBusOff:
      return BusState::kBusOff;
    case BusEventKind::kRestarted:
    case BusEventKind::kErrorActive:
      return BusState::kErrorActive;
    // Linux reports the level of the worse counter, so a warning after passive is a recovery.
    case BusEventKind::kErrorPassive:
      return BusState::kErrorPassive;
    case BusEventKind::kErrorWarning:
      // When one frame says RX passive and TX warning, passive (reported first) must stand.
      return state == BusState::kErrorPassive &&
                     event.frame.data[1] & (can_error::kCtrlRxPassive | can_error::kCtrlTxPassive)
                 ? BusState::kErrorPassive
                 : BusState::kErrorWarning;
    default:
      return state;
  }
}

std::optional<BusState> AnnouncedBusState(std::span<const BusEvent> events) {
  // DecodeErrorFrame lists state events most severe first, so the first one decides.
  for (const BusEvent& event : events) {
    switch (event.kind) {
      case BusEventKind::kBusOff:
      case BusEventKind::kRestarted:
      case BusEventKind::kErrorPassive:
      case BusEventKind::kErrorWarning:
      case BusEventKind::kErrorActive:
        return NextBusState(BusState::kErrorActive, event);
      default:
        break;
    }
  }
  return std::nullopt;
}

}  // namespace hilrig::rig
