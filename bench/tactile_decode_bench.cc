// The DUT's per-sample tactile cost: S(B) (tactile_decoding.h) in double and float, and one whole
// tactile sample through the front end (codes -> tesla, geomagnetic compensation, S(B), a S + b).
// Fields sweep the working volume so branch prediction sees a realistic mix.
#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "dut_fw/tactile_decoding.h"
#include "dut_fw/tactile_processor.h"

namespace hilrig::dut_fw {
namespace {

// Our film's fitted constants (README): k1 1.443, c1 -0.75 mT, k2 0.977, c2 -0.41 mT.
template <typename S>
FilmConstants<S> OurFilm() {
  return {S(1.443), S(-0.75e-3), S(0.977), S(-0.41e-3)};
}

// Fields of the order the chip sees: |Bz| a few mT, shear components up to a mT.
template <typename S>
std::vector<Vec3<S>> Fields() {
  std::vector<Vec3<S>> fields;
  for (int i = 0; i < 64; ++i) {
    const double t = i / 63.0;
    fields.emplace_back(S(1e-3 * (t - 0.5)), S(0.8e-3 * (0.5 - t * t)), S(-4e-3 - 2e-3 * t));
  }
  return fields;
}

template <typename S>
void BM_ComputeS(benchmark::State& state) {
  const FilmConstants<S> film = OurFilm<S>();
  const std::vector<Vec3<S>> fields = Fields<S>();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ComputeS<S>(film, fields[i++ & 63]));
  }
}
BENCHMARK(BM_ComputeS<double>);
BENCHMARK(BM_ComputeS<float>);

void BM_TactileSample(benchmark::State& state) {
  TactileProcessorParams<double> params;
  params.film = OurFilm<double>();
  for (std::size_t n = 0; n < tactile_bus::kTactileNodeCount; ++n) {
    params.nodes[n].node_id = static_cast<std::uint8_t>(n + 1);
    params.nodes[n].gain_a = Vec3<double>(1.0, 1.0, 1.0);
  }
  params.zeroing_samples = 1;
  TactileProcessorState<double> processor;
  // RES 0 words are two's complement: Earth's field of ~50 uT at the reference, and a loaded pad
  // (0.15 mT, 0.08 mT, -4.8 mT) at the tactile node.
  const std::array<std::uint16_t, 3> reference_codes = {200, 65436, 65336};
  const std::array<std::uint16_t, 3> codes = {1000, 500, 45536};
  std::int64_t now_ns = 0;
  std::uint8_t sequence = 0;
  for (auto _ : state) {
    now_ns += 20'000'000;
    OnReferenceSample(params, processor, reference_codes, sequence, false, now_ns);
    OnTactileSample(params, processor, 1, codes, sequence, false, now_ns);
    ++sequence;
    benchmark::DoNotOptimize(processor.nodes[0].force_sensor_n);
  }
  if (processor.nodes[0].flagged != 0) state.SkipWithError("the benchmark's samples were flagged");
}
BENCHMARK(BM_TactileSample);

}  // namespace
}  // namespace hilrig::dut_fw
