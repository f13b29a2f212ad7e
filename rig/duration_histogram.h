// Percentiles of a stream of durations (loop periods, DUT response latencies) in bounded memory: a
// run of any length adds each sample in O(1) to 1 µs buckets up to 100 ms, and keeps the exact
// maximum and mean, so the report's p50 / p99 are exact to the microsecond and the max is exact.
// Samples past the last bucket count in an overflow bucket: a percentile that lands there reads
// as the exact maximum, never as a made-up number. Negative or absurd inputs are counted apart
// (`rejected`) instead of skewing the figures.
#pragma once

#include <cstdint>
#include <vector>

namespace hilrig::rig {

struct DurationSummary {
  std::uint64_t count = 0;
  std::uint64_t rejected = 0;  // negative samples (a clock read out of order)
  double mean_s = 0;
  double p50_s = 0;
  double p99_s = 0;
  double max_s = 0;
};

class DurationHistogram {
 public:
  static constexpr std::int64_t kBucketNs = 1'000;
  static constexpr std::int64_t kRangeNs = 100'000'000;

  DurationHistogram();

  void Add(std::int64_t duration_ns);
  // The q-quantile (0 <= q <= 1) in seconds, to the bucket's upper edge, or the exact maximum when
  // it falls among the overflowed samples; 0 when empty.
  double QuantileS(double q) const;
  DurationSummary Summary() const;
  std::uint64_t count() const { return count_; }

 private:
  std::vector<std::uint64_t> buckets_;  // kRangeNs / kBucketNs of them, then one overflow
  std::uint64_t count_ = 0;
  std::uint64_t rejected_ = 0;
  std::int64_t max_ns_ = 0;
  double sum_ns_ = 0;
};

}  // namespace hilrig::rig
