#include "rig/clock.h"

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

}  // namespace hilrig::rig
