// Clock is the only source of "now" in the rig. Emulated runs use SimClock, which moves only when
// the runner advances it, so a run is reproducible to the byte; bench runs use SteadyClock. No
// other code may read the OS clock: everything else takes `now_ns` or `dt_ns` as an argument.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>

namespace hilrig::rig {

// `time_ns` in seconds. Divides rather than multiplies by 1e-9, so that whole milliseconds come
// out as 0.03, not 0.030000000000000002 (traces print them). O(1); cannot fail.
constexpr double SecondsFromNs(std::int64_t time_ns) { return static_cast<double>(time_ns) / 1e9; }
// `seconds` in whole nanoseconds, rounded to the nearest. O(1); cannot fail.
inline std::int64_t NsFromSeconds(double seconds) { return std::llround(seconds * 1e9); }

class Clock {
 public:
  virtual ~Clock() = default;
  virtual std::int64_t NowNs() const = 0;
};

class SimClock final : public Clock {
 public:
  explicit SimClock(std::int64_t start_ns = 0);
  std::int64_t NowNs() const override;
  // Time never runs backwards: a negative step aborts.
  void AdvanceNs(std::int64_t dt_ns);

 private:
  std::int64_t now_ns_;
};

// A clock a real-time run is paced by: it can also wait until a time on itself. The runner never
// sleeps any other way, so tests pace a run with FakePacingClock and no wall time passes.
class PacingClock : public Clock {
 public:
  // Returns at once when `wall_ns` is not in the future.
  virtual void SleepUntilNs(std::int64_t wall_ns) const = 0;
};

// Counts from construction, so bench traces start near zero like simulated ones.
class SteadyClock final : public PacingClock {
 public:
  SteadyClock();
  std::int64_t NowNs() const override;
  void SleepUntilNs(std::int64_t wall_ns) const override;

 private:
  std::chrono::steady_clock::time_point start_;
};

// A pacing clock for tests: sleeping jumps to the deadline at once (never back), and the test adds
// "work" with AdvanceNs, so late ticks, stalls and periods are exact numbers. Its time is
// `mutable` because a pacing clock is handed to the runner as const, like the real one.
class FakePacingClock final : public PacingClock {
 public:
  explicit FakePacingClock(std::int64_t start_ns = 0);
  std::int64_t NowNs() const override;
  void SleepUntilNs(std::int64_t wall_ns) const override;
  // Time spent working; a negative step aborts.
  void AdvanceNs(std::int64_t dt_ns) const;
  // How many SleepUntilNs calls had to wait (the deadline was in the future).
  std::uint64_t sleeps() const { return sleeps_; }

 private:
  mutable std::int64_t now_ns_;
  mutable std::uint64_t sleeps_ = 0;
};

}  // namespace hilrig::rig
