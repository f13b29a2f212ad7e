// Clock is the only source of "now" in the rig. Emulated runs use SimClock, which moves only when
// the runner advances it, so a run is reproducible to the byte; bench runs use SteadyClock. No
// other code may read the OS clock: everything else takes `now_ns` or `dt_ns` as an argument.
#pragma once

#include <chrono>
#include <cstdint>

namespace hilrig::rig {

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

// Counts from construction, so bench traces start near zero like simulated ones.
class SteadyClock final : public Clock {
 public:
  SteadyClock();
  std::int64_t NowNs() const override;

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace hilrig::rig
