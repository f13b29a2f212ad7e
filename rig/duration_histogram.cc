#include "rig/duration_histogram.h"

#include <algorithm>

#include "rig/nearest_rank.h"

namespace hilrig::rig {
namespace {

constexpr std::size_t kRegularBuckets =
    static_cast<std::size_t>(DurationHistogram::kRangeNs / DurationHistogram::kBucketNs);

}  // namespace

DurationHistogram::DurationHistogram() : buckets_(kRegularBuckets + 1, 0) {}

void DurationHistogram::Add(std::int64_t duration_ns) {
  if (duration_ns < 0) {
    ++rejected_;
    return;
  }
  // Bucket i holds (i, i + 1] µs, so that whole microseconds read back as themselves.
  const std::int64_t index_ns = duration_ns > 0 ? duration_ns - 1 : 0;
  const auto bucket = std::min(static_cast<std::size_t>(index_ns / kBucketNs), kRegularBuckets);
  ++buckets_[bucket];
  ++count_;
  max_ns_ = std::max(max_ns_, duration_ns);
  sum_ns_ += static_cast<double>(duration_ns);
}

double DurationHistogram::QuantileS(double q) const {
  if (count_ == 0 || !(q >= 0)) return 0;
  const std::uint64_t rank = NearestRank(q, count_);
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kRegularBuckets; ++i) {
    seen += buckets_[i];
    if (seen >= rank) {
      const std::int64_t upper_ns = static_cast<std::int64_t>(i + 1) * kBucketNs;
      return static_cast<double>(std::min(upper_ns, max_ns_)) * 1e-9;
    }
  }
  return static_cast<double>(max_ns_) * 1e-9;
}

DurationSummary DurationHistogram::Summary() const {
  DurationSummary summary;
  summary.count = count_;
  summary.rejected = rejected_;
  if (count_ == 0) return summary;
  summary.mean_s = sum_ns_ / static_cast<double>(count_) * 1e-9;
  summary.p50_s = QuantileS(0.5);
  summary.p99_s = QuantileS(0.99);
  summary.max_s = static_cast<double>(max_ns_) * 1e-9;
  return summary;
}

}  // namespace hilrig::rig
