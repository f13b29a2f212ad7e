// Whole shipped scenes, start to end, timed as `hilrig bench` times a sweep's runs: the stepping
// loop only, without the trace or the CAN log (their formatting is measured on its own in
// format_bench.cc); building the runner, the film field and the calibration stay outside the
// timing. Each scene reports its real-time factor (simulated seconds per wall second) and the wall
// time per 1 ms physics tick:
//   build/bin/hilrig_bench --benchmark_filter=Scene --benchmark_repetitions=5
//                          --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>

#include "bench/shipped_scene.h"
#include "host/report/stop_reason.h"
#include "host/runner/runner.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

// The shipped scene `name` as it is run: its own noise, seed, integrator and duration.
void BM_Scene(benchmark::State& state, const char* name) {
  const ScenarioConfig config = ShippedScene(name);
  const rig::SteadyClock wall_clock;
  double simulated_s = 0;
  std::uint64_t ticks = 0;
  std::int64_t wall_ns = 0;  // the stepping loops only, as the benchmark's own time
  for (auto _ : state) {
    state.PauseTiming();
    auto runner = std::make_unique<ScenarioRunner>(config, RunSinks{}, RunControl{&wall_clock});
    state.ResumeTiming();
    const std::int64_t start_ns = wall_clock.NowNs();
    while (runner->Tick()) ++ticks;
    ++ticks;  // the tick that ended the run was stepped too
    wall_ns += wall_clock.NowNs() - start_ns;
    state.PauseTiming();
    const proto::Report report = runner->Finish();
    runner.reset();
    if (!RunCompleted(report)) {
      state.SkipWithError(("the scene stopped: " + report.stop_reason()).c_str());
    }
    simulated_s += report.simulated_s();
    state.ResumeTiming();
  }
  if (ticks == 0 || wall_ns <= 0) return;
  state.counters["real_time_factor"] = simulated_s / (1e-9 * static_cast<double>(wall_ns));
  state.counters["ns_per_tick"] = static_cast<double>(wall_ns) / static_cast<double>(ticks);
}

// One benchmark per grasp scene, each a whole run, so milliseconds and wall time.
#define HILRIG_SCENE_BENCHMARK(name) \
  BENCHMARK_CAPTURE(BM_Scene, name, #name)->Unit(benchmark::kMillisecond)->UseRealTime()
HILRIG_SCENE_BENCHMARK(balloon_grasp);
HILRIG_SCENE_BENCHMARK(load_ramp);
HILRIG_SCENE_BENCHMARK(objects);
HILRIG_SCENE_BENCHMARK(bottle_feedback);
HILRIG_SCENE_BENCHMARK(bottle_ablation);

}  // namespace
}  // namespace hilrig::host
