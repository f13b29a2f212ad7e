#include "rig/can_bus.h"

#include <algorithm>

namespace hilrig::rig {
namespace {

bool Matches(const CanFilter& filter, const CanFrame& frame) {
  const bool hit = ((frame.id ^ filter.id) & filter.mask) == 0 && frame.extended == filter.extended;
  return hit != filter.inverted;
}

}  // namespace

bool FilterAccepts(std::span<const CanFilter> filters, const CanFrame& frame) {
  if (filters.empty()) return true;
  return std::any_of(filters.begin(), filters.end(),
                     [&frame](const CanFilter& filter) { return Matches(filter, frame); });
}

}  // namespace hilrig::rig
