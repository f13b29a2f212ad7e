// Replays a candump -l log into a CanBus at the recorded pace or faster: frame k is sent when the
// replay's time reaches (t_k - t_0) / speed after its start. Time is injected: the caller ticks the
// replay with `now_ns` from a SimClock (lockstep runs) or the SteadyClock (bench), and the first
// Tick marks the start. TX-marked lines (" T") are what the recording node itself sent; they are
// replayed like any other frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "rig/can_bus.h"
#include "rig/result.h"

namespace hilrig::rig {

// The longest candump line is under 200 bytes (a CAN FD frame's 64 data bytes in hex, a 16-byte
// interface name, a 20-digit timestamp); a longer one is not a log line.
inline constexpr std::size_t kMaxCandumpLineBytes = 1024;

class CandumpReplay {
 public:
  // Reads the whole log; errors name the line, and a line longer than kMaxCandumpLineBytes is
  // one. `speed` > 0 (1 = recorded time).
  static Result<CandumpReplay> Read(std::istream& log, double speed);

  // Sends every frame due at `now_ns`; returns how many went out (a failed send is counted and
  // skipped, as a node whose frame the bus refused).
  std::size_t Tick(std::int64_t now_ns, CanBus& bus);

  bool done() const { return next_ >= frames_.size(); }
  std::size_t size() const { return frames_.size(); }
  std::uint64_t send_failures() const { return send_failures_; }

 private:
  CandumpReplay(std::vector<TimedCanFrame> frames, double speed);

  std::vector<TimedCanFrame> frames_;  // time_ns relative to the first frame
  double speed_;
  std::size_t next_ = 0;
  bool started_ = false;
  std::int64_t start_ns_ = 0;
  std::uint64_t send_failures_ = 0;
};

}  // namespace hilrig::rig
