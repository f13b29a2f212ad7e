// Benchmarks of the sensor emulators' per-tick hot paths: the Gaussian noise draws (twelve per IMU
// sample, three per Hall sample), one IMU sample, one tactile node's forward model (silicone step,
// film field, Earth field, MLX90393 conversion) with its constants built once as the node does,
// and the field map lookup of an un-tilted film.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>

#include "host/sensors/earth_field.h"
#include "host/sensors/imu_emulator.h"
#include "host/sensors/random_stream.h"
#include "host/sensors/tactile/dipole_film_field.h"
#include "host/sensors/tactile/field_map.h"
#include "host/sensors/tactile/tactile_sensor.h"

namespace hilrig::host {
namespace {

void BM_StandardGaussianVector(benchmark::State& state) {
  RandomStream rng = RandomStream::FromSeed(1, StreamId::kImu);
  for (auto _ : state) benchmark::DoNotOptimize(StandardGaussianVector(rng));
}
BENCHMARK(BM_StandardGaussianVector);

void BM_SampleImu(benchmark::State& state) {
  const ImuParams params;
  ImuState imu = MakeImuState(params, RandomStream::FromSeed(1, StreamId::kImu));
  const Eigen::Vector3d rate_rad_s(0.01, -0.02, 0.03);
  const Eigen::Vector3d specific_force_m_s2(0.0, 0.0, 9.81);
  std::int64_t now_ns = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(SampleImu(params, imu, rate_rad_s, specific_force_m_s2, now_ns));
    now_ns += 1'000'000;
  }
}
BENCHMARK(BM_SampleImu);

// A pad under a slowly changing load, so that every sample moves the film (no memo hit).
void BM_SampleTactileSensor(benchmark::State& state) {
  const TactileSensorParams params;
  const DipoleFilmField film = DipoleFilmField::FromFilm(FilmGeometry{});
  const TactileSensorConstants constants = MakeTactileSensorConstants(params, 1e-3);
  TactileSensorState sensor = InitialTactileSensorState(params, 1);
  const Eigen::Quaterniond attitude(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  // Rotated by the attitude once per tick for every sensor on the vehicle, so not part of a sample.
  const Eigen::Vector3d earth_body_t =
      EarthFieldInBodyFrame(attitude, Eigen::Vector3d(0.0, 2.4e-5, -4.16e-5));
  Eigen::Vector3d force_n(0.1, -0.05, 0.5);
  for (auto _ : state) {
    force_n.z() += 1e-6;
    benchmark::DoNotOptimize(SampleTactileSensor(params, constants, sensor, film, force_n,
                                                 earth_body_t, 25.0, Eigen::Vector3d::Zero()));
  }
}
BENCHMARK(BM_SampleTactileSensor);

void BM_FieldMapLookupUntilted(benchmark::State& state) {
  const FieldMapFilmField map(
      std::make_shared<const DipoleFilmField>(DipoleFilmField::FromFilm(FilmGeometry{})));
  FilmPose pose;
  pose.centre_m = Eigen::Vector3d(0.0011, -0.0007, -0.0093);
  for (auto _ : state) {
    pose.centre_m.z() += 1e-12;
    benchmark::DoNotOptimize(map.Lookup(pose));
  }
}
BENCHMARK(BM_FieldMapLookupUntilted);

}  // namespace
}  // namespace hilrig::host
