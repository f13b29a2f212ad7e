#include "rig/value_counts.h"

#include <algorithm>
#include <cmath>

namespace hilrig::rig {

std::uint32_t ValueCounts::Quantile(double q) const {
  if (count_ == 0) return 0;
  const double clamped = std::isnan(q) ? 0.0 : std::clamp(q, 0.0, 1.0);
  const auto rank = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::ceil(clamped * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (const auto& [value, count] : counts_) {
    seen += count;
    if (seen >= rank) return value;
  }
  return max();
}

}  // namespace hilrig::rig
