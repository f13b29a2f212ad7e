#include "host/runner/realtime_pacer.h"

#include <algorithm>

namespace hilrig::host {
namespace {

using rig::SecondsFromNs;

proto::StreamLatency ToProto(const StreamLatency& latency) {
  proto::StreamLatency stream;
  stream.set_stream(latency.stream);
  stream.set_count(latency.latency.count);
  stream.set_p50_s(latency.latency.p50_s);
  stream.set_p99_s(latency.latency.p99_s);
  stream.set_max_s(latency.latency.max_s);
  stream.set_mean_s(latency.latency.mean_s);
  return stream;
}

}  // namespace

RealtimePacer::RealtimePacer(const rig::PacingClock& clock, const PacerSettings& settings)
    : clock_(clock), settings_(settings) {}

void RealtimePacer::WaitUntil(std::int64_t due_ns,
                              const std::function<void()>& while_waiting) const {
  if (!while_waiting || settings_.wait_slice_ns <= 0) {
    clock_.SleepUntilNs(due_ns);
    return;
  }
  for (std::int64_t now_ns = clock_.NowNs(); now_ns < due_ns; now_ns = clock_.NowNs()) {
    while_waiting();
    clock_.SleepUntilNs(std::min(due_ns, now_ns + settings_.wait_slice_ns));
  }
}

void RealtimePacer::BeginTick(std::uint64_t tick, const std::function<void()>& while_waiting) {
  if (!epoch_ns_) {
    // Tick numbers count from the first paced tick, whatever the caller's count is.
    epoch_ns_ = clock_.NowNs() - static_cast<std::int64_t>(tick) * settings_.period_ns;
  }
  const std::int64_t due_ns = *epoch_ns_ + static_cast<std::int64_t>(tick) * settings_.period_ns;
  WaitUntil(due_ns, while_waiting);
  const std::int64_t start_ns = clock_.NowNs();
  if (ticks_ > 0) period_.Add(start_ns - tick_start_ns_);
  const std::int64_t lateness_ns = start_ns - due_ns;
  lateness_.Add(lateness_ns);
  if (lateness_ns > settings_.late_threshold_ns) ++late_ticks_;
  const bool behind = lateness_ns > settings_.stall_threshold_ns;
  if (behind && !behind_) ++stalls_;
  behind_ = behind;
  tick_start_ns_ = start_ns;
  ++ticks_;
}

void RealtimePacer::EndTick() { work_.Add(clock_.NowNs() - tick_start_ns_); }

void RealtimePacer::CountControlTick(bool new_command) {
  if (control_ticks_ > 0 && !new_command) ++commands_missed_;
  ++control_ticks_;
}

proto::Timing RealtimePacer::Figures(const std::vector<StreamLatency>& latencies) const {
  proto::Timing timing;
  timing.set_mode("realtime");
  timing.set_ticks(ticks_);
  timing.set_period_s(SecondsFromNs(settings_.period_ns));
  const rig::DurationSummary period = period_.Summary();
  timing.set_loop_period_p50_s(period.p50_s);
  timing.set_loop_period_p99_s(period.p99_s);
  timing.set_loop_period_max_s(period.max_s);
  timing.set_loop_period_mean_s(period.mean_s);
  const rig::DurationSummary lateness = lateness_.Summary();
  timing.set_lateness_p99_s(lateness.p99_s);
  timing.set_lateness_max_s(lateness.max_s);
  timing.set_late_threshold_s(SecondsFromNs(settings_.late_threshold_ns));
  timing.set_late_ticks(late_ticks_);
  timing.set_stalls(stalls_);
  const rig::DurationSummary work = work_.Summary();
  timing.set_work_p50_s(work.p50_s);
  timing.set_work_p99_s(work.p99_s);
  timing.set_work_max_s(work.max_s);
  timing.set_control_ticks(control_ticks_);
  timing.set_dut_commands_missed(commands_missed_);
  for (const StreamLatency& latency : latencies) *timing.add_dut_latency() = ToProto(latency);
  return timing;
}

}  // namespace hilrig::host
