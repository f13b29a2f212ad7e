#include "rig/clock.h"

#include <thread>

#include "rig/check.h"

namespace hilrig::rig {

SimClock::SimClock(std::int64_t start_ns) : now_ns_(start_ns) {}

std::int64_t SimClock::NowNs() const { return now_ns_; }

void SimClock::AdvanceNs(std::int64_t dt_ns) {
  HILRIG_CHECK(dt_ns >= 0, "SimClock cannot run backwards");
  now_ns_ += dt_ns;
}

SteadyClock::SteadyClock() : start_(std::chrono::steady_clock::now()) {}

std::int64_t SteadyClock::NowNs() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                              start_)
      .count();
}

// A plain sleep: on the 2-core development VM it wakes ~120 us late at p50 and 0.2-3.7 ms at p99
// (bench/clock_bench.cc). Sleeping to 0.5 ms short and spinning the rest fixed that for an
// in-process DUT (late ticks 3.7 % -> 0.7 %) but starved a DUT process sharing the two cores (late
// ticks 4.6-9 %, missed commands 18-27 %), so the loop sleeps.
void SteadyClock::SleepUntilNs(std::int64_t wall_ns) const {
  std::this_thread::sleep_until(start_ + std::chrono::nanoseconds(wall_ns));
}

FakePacingClock::FakePacingClock(std::int64_t start_ns) : now_ns_(start_ns) {}

std::int64_t FakePacingClock::NowNs() const { return now_ns_; }

void FakePacingClock::SleepUntilNs(std::int64_t wall_ns) const {
  if (wall_ns <= now_ns_) return;
  now_ns_ = wall_ns;
  ++sleeps_;
}

void FakePacingClock::AdvanceNs(std::int64_t dt_ns) const {
  HILRIG_CHECK(dt_ns >= 0, "FakePacingClock cannot run backwards");
  now_ns_ += dt_ns;
}

}  // namespace hilrig::rig
