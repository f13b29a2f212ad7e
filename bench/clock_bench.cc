// How late the wall clock's sleep wakes a real-time loop on this machine: SteadyClock::SleepUntilNs
// to deadlines 1 ms apart, as the runner's pacing does, with the overshoot past each deadline kept
// in a DurationHistogram. A real-time run's late ticks are bounded below by this, not by the tick's
// work (README "Real time").
#include <benchmark/benchmark.h>

#include "rig/clock.h"
#include "rig/duration_histogram.h"

namespace hilrig::rig {
namespace {

void BM_SleepUntilOvershoot(benchmark::State& state) {
  const SteadyClock clock;
  DurationHistogram overshoot;
  std::int64_t deadline_ns = clock.NowNs();
  for (auto _ : state) {
    deadline_ns += 1'000'000;
    clock.SleepUntilNs(deadline_ns);
    overshoot.Add(clock.NowNs() - deadline_ns);
  }
  const DurationSummary summary = overshoot.Summary();
  state.counters["overshoot_p50_us"] = summary.p50_s * 1e6;
  state.counters["overshoot_p99_us"] = summary.p99_s * 1e6;
  state.counters["overshoot_max_us"] = summary.max_s * 1e6;
}
BENCHMARK(BM_SleepUntilOvershoot)->Iterations(5000)->UseRealTime();

}  // namespace
}  // namespace hilrig::rig
