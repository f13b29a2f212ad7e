// The DUT's optional tactile force filter: the mean of a pad's last n decoded forces. The chip's
// noise dominates the held-out force error (`hilrig accuracy --budget`); averaging n samples
// divides it by sqrt(n) and delays a step in force by (n - 1) / 2 sample periods on average
// (30 ms for n = 4 at 50 Hz), a whole n - 1 periods until the step is through. n = 1 is no filter.
//
// Portable like the rest of dut_fw: fixed storage of kMaxSamples, no allocation, no exceptions.
#pragma once

#include <array>

#include "dut_fw/types.h"

namespace hilrig::dut_fw {

template <typename S, int kMaxSamples = 16>
class ForceAverage {
 public:
  // No filter (n = 1); implicit so that a state holding one can be reset with `= {}`.
  ForceAverage() : ForceAverage(1) {}
  // n is clamped to 1..kMaxSamples. Starts empty. Cannot fail.
  explicit ForceAverage(int samples)
      : samples_(samples < 1 ? 1 : (samples > kMaxSamples ? kMaxSamples : samples)) {}

  int samples() const { return samples_; }

  // Forgets every sample: after a reading the decoder flagged, the next mean starts afresh rather
  // than mixing forces from before the gap. O(1).
  void Reset() {
    count_ = 0;
    next_ = 0;
    sum_.setZero();
  }

  // Adds a decoded force and returns the mean of the last min(n, added) of them. O(1) amortised:
  // the running sum is rebuilt from the kept samples once per n calls, so rounding does not
  // accumulate over a long run. Does not allocate; cannot fail.
  Vec3<S> Add(const Vec3<S>& force_n) {
    if (count_ == samples_) sum_ -= ring_[next_];
    ring_[next_] = force_n;
    sum_ += force_n;
    next_ = next_ + 1 == samples_ ? 0 : next_ + 1;
    if (count_ < samples_) ++count_;
    if (next_ == 0) {
      sum_.setZero();
      for (int i = 0; i < count_; ++i) sum_ += ring_[i];
    }
    return sum_ / static_cast<S>(count_);
  }

 private:
  int samples_;
  int count_ = 0;
  int next_ = 0;
  Vec3<S> sum_ = Vec3<S>::Zero();
  std::array<Vec3<S>, kMaxSamples> ring_{};
};

}  // namespace hilrig::dut_fw
