// Real-time pacing of the runner's loop and the figures it measures. Tick k is due at
// epoch + k * period on a PacingClock (the epoch is the first tick's start); before each tick the
// pacer sleeps until it is due, never when the tick is already late, and never moves the epoch, so
// after a stall the loop runs ticks back to back until it has caught up. It measures the loop
// period, each tick's lateness and work time, late ticks, stalls and the control ticks the DUT
// left without a new command, all in bounded memory (rig/duration_histogram.h).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "host/dut/dut_port.h"
#include "proto/report.pb.h"
#include "rig/clock.h"
#include "rig/duration_histogram.h"

namespace hilrig::host {

struct PacerSettings {
  std::int64_t period_ns = 1'000'000;
  // A tick starting more than this after its due time is late.
  std::int64_t late_threshold_ns = 1'000'000;
  // Falling more than this behind the schedule is a stall (counted once per episode).
  std::int64_t stall_threshold_ns = 100'000'000;
  // While waiting for a tick, wake this often to run the caller's `while_waiting` (the runner
  // polls the DUT there, so that a command's arrival is seen within a slice, not a whole period
  // later, and the measured DUT latency is the DUT's and not the loop's).
  std::int64_t wait_slice_ns = 100'000;
};

class RealtimePacer {
 public:
  // `clock` must outlive the pacer.
  RealtimePacer(const rig::PacingClock& clock, const PacerSettings& settings);

  // Waits until tick `tick` is due (unless it is late already), running `while_waiting` (if any)
  // every wait slice meanwhile, and records the tick's start.
  void BeginTick(std::uint64_t tick, const std::function<void()>& while_waiting = {});
  // Records the wall time since BeginTick as the tick's work.
  void EndTick();
  // Counts one control tick; `new_command`: a command arrived since the previous control tick.
  // The first control tick is never a miss: nothing could have arrived before it.
  void CountControlTick(bool new_command);

  // The figures so far, mode "realtime", with the DUT's per-stream latencies.
  proto::Timing Figures(const std::vector<StreamLatency>& latencies) const;

  std::uint64_t late_ticks() const { return late_ticks_; }
  std::uint64_t stalls() const { return stalls_; }
  std::uint64_t dut_commands_missed() const { return commands_missed_; }

 private:
  void WaitUntil(std::int64_t due_ns, const std::function<void()>& while_waiting) const;

  const rig::PacingClock& clock_;
  PacerSettings settings_;
  std::optional<std::int64_t> epoch_ns_;
  std::int64_t tick_start_ns_ = 0;
  bool behind_ = false;  // in a stall episode
  rig::DurationHistogram period_;
  rig::DurationHistogram lateness_;
  rig::DurationHistogram work_;
  std::uint64_t ticks_ = 0;
  std::uint64_t late_ticks_ = 0;
  std::uint64_t stalls_ = 0;
  std::uint64_t control_ticks_ = 0;
  std::uint64_t commands_missed_ = 0;
};

}  // namespace hilrig::host
