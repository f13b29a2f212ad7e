// Exact percentiles of a stream of whole-number samples (a target's work per control step in
// cycles) in memory that grows with the number of distinct values, not with the number of samples:
// a work figure spans a few thousand values, so an hour at 1 kHz costs the same as a second.
// Percentiles are nearest rank (the smallest sample with at least q of all samples at or below
// it), exact, never interpolated.
#pragma once

#include <cstdint>
#include <map>

namespace hilrig::rig {

class ValueCounts {
 public:
  // O(log distinct values); allocates only for a value not seen before.
  void Add(std::uint32_t value) {
    ++counts_[value];
    ++count_;
  }
  // The q-quantile (0 <= q <= 1, clamped) by nearest rank; 0 when empty. O(distinct values).
  std::uint32_t Quantile(double q) const;
  std::uint32_t max() const { return counts_.empty() ? 0 : counts_.rbegin()->first; }
  std::uint64_t count() const { return count_; }

 private:
  std::map<std::uint32_t, std::uint64_t> counts_;
  std::uint64_t count_ = 0;
};

}  // namespace hilrig::rig
