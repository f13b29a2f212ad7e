// A plotted signal kept in bounded memory however long the run: samples fall into buckets of
// equal sample count, and each bucket keeps its first, last, lowest and highest finite sample and
// where it had a gap (a non-finite time or value). When the buckets are full, neighbours merge in
// pairs and the bucket width doubles, so a series holds at most kMaxBuckets buckets and, once
// merging started, at least kMaxBuckets / 2 -- more than a plot has pixel columns (svg_plot.h).
// A line through each bucket's kept samples in sample order reaches every extreme, so no peak
// drops out of the plot; a series no longer than kMaxBuckets comes back exactly as added.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hilrig::host {

class DecimatedSeries {
 public:
  static constexpr std::size_t kMaxBuckets = 2048;

  // Never fails; a non-finite time or value is kept as a gap in the line.
  void Add(double time_s, double value);

  // The kept samples in the order they were added; a gap is a sample with a NaN value (at the
  // gap's time). Same length; at most 6 x kMaxBuckets.
  struct Points {
    std::vector<double> time_s;
    std::vector<double> value;
  };
  Points ToPoints() const;

  std::uint64_t samples_added() const { return added_n_; }
  std::size_t bucket_count() const { return buckets_.size(); }
  std::uint64_t bucket_width_n() const { return width_n_; }

 private:
  struct Kept {
    std::uint64_t index = 0;  // of the sample, in the order added
    double time_s = 0, value = 0;
  };
  struct Bucket {
    bool any_finite = false, any_gap = false;
    Kept first, last, lowest, highest;  // finite samples; valid when any_finite
    Kept first_gap, last_gap;           // valid when any_gap
  };
  static Bucket Merged(const Bucket& earlier, const Bucket& later);
  void MergePairs();

  std::vector<Bucket> buckets_;
  std::uint64_t width_n_ = 1;  // samples per bucket
  std::uint64_t added_n_ = 0;
};

}  // namespace hilrig::host
