// Work-precision of the film field models: time per FieldAtChip and the maximum relative error
// over the working volume (5^3 poses) against a 128 x 128 tile reference, for N x N tiles, the
// field map (default grid, built from N = 16) and the dipole fake. The error is a counter
// (max_rel_err); the reference is evaluated once per model, outside the timed loop.
#include <benchmark/benchmark.h>

#include <memory>

#include "host/sensors/tactile/dipole_film_field.h"
#include "host/sensors/tactile/field_map.h"
#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {
namespace {

constexpr int kErrorSamplesPerAxis = 5;

const TiledFilmField& Reference() {
  static const TiledFilmField reference(FilmGeometry{}, 128);
  return reference;
}

// Poses cycled through in the timed loop, so that no single pose's branch pattern is favoured.
FilmPose Pose(int i) {
  FilmPose pose;
  pose.centre_m =
      Eigen::Vector3d(0.0005 * (i % 7 - 3), 0.0005 * (i % 5 - 2), -0.010 + 0.0004 * (i % 9 - 4));
  return pose;
}

void Run(benchmark::State& state, const FilmFieldModel& model) {
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.FieldAtChip(Pose(i++ % 63)));
  }
  state.counters["max_rel_err"] = MaxRelativeError(model, Reference(), kErrorSamplesPerAxis);
}

void BM_TiledFilmField(benchmark::State& state) {
  const TiledFilmField model(FilmGeometry{}, static_cast<int>(state.range(0)));
  Run(state, model);
}
BENCHMARK(BM_TiledFilmField)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32)
    ->Arg(64)
    ->Unit(benchmark::kMicrosecond);

void BM_FieldMap(benchmark::State& state) {
  const FieldMapFilmField model(std::make_shared<const TiledFilmField>(FilmGeometry{}, 16));
  Run(state, model);
}
BENCHMARK(BM_FieldMap)->Unit(benchmark::kMicrosecond);

void BM_FieldMapBuild(benchmark::State& state) {
  const auto source = std::make_shared<const TiledFilmField>(FilmGeometry{}, 16);
  for (auto _ : state) {
    FieldMapFilmField model(source);
    benchmark::DoNotOptimize(&model);
  }
}
BENCHMARK(BM_FieldMapBuild)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_DipoleFilmField(benchmark::State& state) {
  const DipoleFilmField model = DipoleFilmField::FromFilm(FilmGeometry{});
  Run(state, model);
}
BENCHMARK(BM_DipoleFilmField)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hilrig::host
