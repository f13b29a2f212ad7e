#include "rig/value_counts.h"

#include "rig/nearest_rank.h"

namespace hilrig::rig {

std::uint32_t ValueCounts::Quantile(double q) const {
  if (count_ == 0) return 0;
  const std::uint64_t rank = NearestRank(q, count_);
  std::uint64_t seen = 0;
  for (const auto& [value, count] : counts_) {
    seen += count;
    if (seen >= rank) return value;
  }
  return max();
}

}  // namespace hilrig::rig
