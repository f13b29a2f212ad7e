// The mean of a signal over a trailing time window (an envelope's mean_over_s), at O(1) amortised
// cost per sample however many samples the window holds. The finite values are summed as they come
// and go, and summed afresh from the window's start once per window's worth of departures, so
// rounding cannot build up over a long run; the non-finite ones are counted, so that a NaN or an
// infinity rules the mean while it is in the window (NaN for a NaN or for both infinities, as a
// plain sum gives) and stops ruling it when it leaves.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

namespace hilrig::host {

class TrailingMean {
 public:
  // Appends `value` at `time_s` (times do not decrease), then drops every sample at least
  // `span_s` older than it (the new one too when span_s <= 0).
  void Add(double time_s, double value, double span_s);

  // The mean of the samples in the window; NaN when it holds none (0 / 0).
  double Mean() const;

  std::size_t size() const { return samples_.size(); }
  // Values added into a sum so far, counting the fresh sums: at most about three per sample added.
  std::uint64_t values_summed() const { return values_summed_; }

 private:
  void Count(double value, bool arriving);
  void Resum();

  std::deque<std::pair<double, double>> samples_;  // (time, value)
  double finite_sum_ = 0;
  // The values left out of finite_sum_, by kind.
  struct {
    std::size_t nan = 0, positive_infinity = 0, negative_infinity = 0;
  } non_finite_;
  std::size_t departures_since_resum_ = 0;
  std::uint64_t values_summed_ = 0;
};

}  // namespace hilrig::host
