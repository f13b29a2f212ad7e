#include "host/trace/decimated_series.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hilrig::host {

void DecimatedSeries::Add(double time_s, double value) {
  if (added_n_ / width_n_ == buckets_.size()) {
    if (buckets_.size() == kMaxBuckets) MergePairs();
    if (added_n_ / width_n_ == buckets_.size()) buckets_.emplace_back();
  }
  Bucket& bucket = buckets_.back();
  const Kept sample{added_n_++, time_s, value};
  if (!std::isfinite(time_s) || !std::isfinite(value)) {
    if (!bucket.any_gap) bucket.first_gap = sample;
    bucket.last_gap = sample;
    bucket.any_gap = true;
    return;
  }
  if (!bucket.any_finite) {
    bucket.first = bucket.lowest = bucket.highest = sample;
    bucket.any_finite = true;
  }
  bucket.last = sample;
  if (value < bucket.lowest.value) bucket.lowest = sample;
  if (value > bucket.highest.value) bucket.highest = sample;
}

DecimatedSeries::Bucket DecimatedSeries::Merged(const Bucket& earlier, const Bucket& later) {
  Bucket merged = earlier;
  if (later.any_finite) {
    if (!earlier.any_finite) {
      merged.first = later.first;
      merged.lowest = later.lowest;
      merged.highest = later.highest;
    } else {
      // Ties keep the earlier sample, as a bucket filled sample by sample does.
      if (later.lowest.value < merged.lowest.value) merged.lowest = later.lowest;
      if (later.highest.value > merged.highest.value) merged.highest = later.highest;
    }
    merged.last = later.last;
    merged.any_finite = true;
  }
  if (later.any_gap) {
    if (!earlier.any_gap) merged.first_gap = later.first_gap;
    merged.last_gap = later.last_gap;
    merged.any_gap = true;
  }
  return merged;
}

void DecimatedSeries::MergePairs() {
  const std::size_t half = buckets_.size() / 2;
  for (std::size_t i = 0; i < half; ++i) {
    buckets_[i] = Merged(buckets_[2 * i], buckets_[2 * i + 1]);
  }
  if (buckets_.size() % 2 == 1) {
    buckets_[half] = buckets_.back();
    buckets_.resize(half + 1);
  } else {
    buckets_.resize(half);
  }
  width_n_ *= 2;
}

DecimatedSeries::Points DecimatedSeries::ToPoints() const {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  Points points;
  for (const Bucket& bucket : buckets_) {
    // The unused entries sort last, so the whole array sorts: a sort over its first n entries
    // makes GCC 12 warn of bounds it cannot see are kept (-Warray-bounds).
    std::array<Kept, 6> kept;
    kept.fill(Kept{std::numeric_limits<std::uint64_t>::max(), 0, 0});
    std::size_t n = 0;
    if (bucket.any_finite) {
      for (const Kept& k : {bucket.first, bucket.lowest, bucket.highest, bucket.last})
        kept[n++] = k;
    }
    if (bucket.any_gap) {
      for (const Kept& k : {bucket.first_gap, bucket.last_gap}) kept[n++] = k;
    }
    std::sort(kept.begin(), kept.end(),
              [](const Kept& a, const Kept& b) { return a.index < b.index; });
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0 && kept[i].index == kept[i - 1].index) continue;
      const bool finite = std::isfinite(kept[i].time_s) && std::isfinite(kept[i].value);
      points.time_s.push_back(kept[i].time_s);
      points.value.push_back(finite ? kept[i].value : kNaN);
    }
  }
  return points;
}

}  // namespace hilrig::host
