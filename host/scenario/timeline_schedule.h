// The timeline as a run reads it tick by tick, at a cost per tick that does not grow with the
// number of timeline entries. TimeCursor walks a list sorted by time forward only, so over a whole
// run each entry is stepped over once. IntervalSumSchedule tabulates the sum of values that each
// hold over an interval [start_s, end_s) (disturbance forces, pour rates, stray fields) once, as a
// piecewise-constant schedule read through such a cursor.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <ranges>
#include <type_traits>
#include <utility>
#include <vector>

namespace hilrig::host {

// How many entries of a list sorted by time lie at or before the time last asked.
class TimeCursor {
 public:
  // `time_of(i)` is entry i's time, for i < `size`. A time that does not decrease costs O(1)
  // amortised; an earlier one is looked up again in O(log size).
  template <typename TimeOf>
  std::size_t Seek(double time_s, std::size_t size, TimeOf time_of) {
    if (passed_ > 0 && time_s < time_of(passed_ - 1)) {
      passed_ = *std::ranges::partition_point(std::views::iota(std::size_t{0}, passed_),
                                              [&](std::size_t i) { return time_of(i) <= time_s; });
    }
    while (passed_ < size && time_of(passed_) <= time_s) {
      ++passed_;
      ++steps_;
    }
    return passed_;
  }

  // Entries stepped over so far: at most the list's size for times that do not decrease, however
  // often Seek() was called.
  std::uint64_t steps() const { return steps_; }

 private:
  std::size_t passed_ = 0;
  std::uint64_t steps_ = 0;
};

template <typename Value>
class IntervalSumSchedule {
 public:
  struct Interval {
    double start_s = 0;
    double end_s = 0;  // exclusive: an interval with end_s <= start_s never holds
    Value value;
  };

  IntervalSumSchedule() = default;
  // Each piece's sum is a pairwise (segment tree) sum over the intervals in their given order,
  // O(log n) per interval boundary; with at most two intervals holding at once it is bit for bit
  // their plain sum.
  explicit IntervalSumSchedule(const std::vector<Interval>& intervals);

  // The sum of the values of the intervals that hold at `time_s` (zero when none does).
  const Value& At(double time_s) {
    const std::size_t passed =
        cursor_.Seek(time_s, pieces_.size(), [this](std::size_t i) { return pieces_[i].start_s; });
    return passed == 0 ? zero_ : pieces_[passed - 1].sum;
  }

  std::size_t piece_count() const { return pieces_.size(); }
  std::uint64_t pieces_stepped() const { return cursor_.steps(); }

 private:
  struct Piece {
    double start_s;
    Value sum;  // holds from start_s until the next piece's start
  };
  static Value Zero() {
    if constexpr (std::is_arithmetic_v<Value>) {
      return Value{0};
    } else {
      return Value::Zero();
    }
  }

  std::vector<Piece> pieces_;  // by increasing start_s
  TimeCursor cursor_;
  Value zero_ = Zero();
};

template <typename Value>
IntervalSumSchedule<Value>::IntervalSumSchedule(const std::vector<Interval>& intervals) {
  struct Boundary {
    double time_s;
    std::size_t interval;
    bool starts;
  };
  std::vector<Boundary> boundaries;
  boundaries.reserve(2 * intervals.size());
  for (std::size_t i = 0; i < intervals.size(); ++i) {
    if (!(intervals[i].end_s > intervals[i].start_s)) continue;
    boundaries.push_back({intervals[i].start_s, i, true});
    boundaries.push_back({intervals[i].end_s, i, false});
  }
  std::sort(boundaries.begin(), boundaries.end(),
            [](const Boundary& a, const Boundary& b) { return a.time_s < b.time_s; });
  // Leaves at [n, 2n), node p = node 2p + node 2p+1, node 1 the sum of all leaves (any n >= 1).
  const std::size_t n = intervals.size();
  std::vector<Value> tree(2 * n, Zero());
  for (std::size_t k = 0; k < boundaries.size();) {
    const double time_s = boundaries[k].time_s;
    for (; k < boundaries.size() && boundaries[k].time_s == time_s; ++k) {
      std::size_t node = n + boundaries[k].interval;
      tree[node] = boundaries[k].starts ? intervals[boundaries[k].interval].value : Zero();
      for (node /= 2; node >= 1; node /= 2) tree[node] = tree[2 * node] + tree[2 * node + 1];
    }
    // Added to zero, as a running sum from zero would be: a lone -0 reads as +0.
    Value sum = Zero();
    sum += tree[1];
    pieces_.push_back({time_s, sum});
  }
}

struct KeepEveryEvent {
  bool operator()(const auto&) const { return true; }
};

// The schedule of the timeline `events` (each has at_s and duration_s) that `keep` accepts, each
// holding value_of(event) from at_s for duration_s.
template <typename Event, typename ValueOf, typename Keep = KeepEveryEvent>
auto EventSchedule(const std::vector<Event>& events, ValueOf value_of, Keep keep = {}) {
  using Value = std::decay_t<decltype(value_of(std::declval<const Event&>()))>;
  std::vector<typename IntervalSumSchedule<Value>::Interval> intervals;
  for (const Event& event : events) {
    if (keep(event)) {
      intervals.push_back({event.at_s, event.at_s + event.duration_s, value_of(event)});
    }
  }
  return IntervalSumSchedule<Value>(intervals);
}

}  // namespace hilrig::host
