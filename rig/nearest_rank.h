// The nearest-rank quantile every summary in the rig reports (a target's work cycles, response
// latencies, a sweep's margins): the q-quantile of n values is the smallest value with at least q
// of them at or below it, exact, never interpolated. One definition, so that they all agree.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hilrig::rig {

// The 1-based rank of the q-quantile among n sorted values: ceil(q·n), at least 1 and at most n
// (1 when n is 0). q is clamped to [0, 1] and a NaN q reads as 0. A q·n within 1e-12 relative of
// a whole number counts as that number: the 0.07-quantile of 100 values is the 7th as written,
// not the 8th that 0.07 · 100 rounds up to in binary. Cannot fail; O(1); does not allocate.
inline std::uint64_t NearestRank(double q, std::uint64_t n) {
  const double clamped = std::isnan(q) ? 0.0 : std::clamp(q, 0.0, 1.0);
  const double count = static_cast<double>(n);
  const double rank = std::ceil(clamped * count * (1 - 1e-12));
  return static_cast<std::uint64_t>(std::clamp(rank, 1.0, std::max(count, 1.0)));
}

}  // namespace hilrig::rig
