#include "rig/can_bus.h"

#include <algorithm>

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

}  // namespace hilrig::rig
