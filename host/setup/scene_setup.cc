#include "host/setup/scene_setup.h"

#include <utility>

#include "fixtures/calibration/calibration_file.h"
#include "fixtures/calibration/calibration_procedure.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

rig::Result<void> BuildFilmField(ScenarioConfig& config, FilmFieldModels* film_models,
                                 const std::atomic<bool>* stop_requested) {
  HallSensorConfig& hall = config.hall_sensors;
  if (!hall.tactile_enabled || hall.film_field != nullptr) return {};
  auto film = film_models != nullptr ? film_models->Get(hall.field_fidelity, stop_requested)
                                     : MakeFilmField(hall.field_fidelity, nullptr, stop_requested);
  if (!film) return film.error();
  hall.film_field = std::move(film).value();
  return {};
}

rig::Result<void> LoadTactileCalibration(ScenarioConfig& config,
                                         const std::atomic<bool>* stop_requested) {
  HallSensorConfig& hall = config.hall_sensors;
  if (!hall.tactile_enabled) return {};
  if (!hall.calibration_file.empty()) {
    auto calibration = fixtures::ReadCalibrationFile(hall.calibration_file);
    if (!calibration) return calibration.error();
    hall.calibration = std::move(calibration).value();
    return {};
  }
  if (auto built = BuildFilmField(config, nullptr, stop_requested); !built) return built.error();
  fixtures::CalibrationBench bench;
  bench.tactile = hall.tactile;
  bench.reference = hall.reference;
  bench.earth_field_world_t = config.earth_field.field_world_t;
  bench.temperature_c = hall.temperature_c;
  hall.calibration =
      fixtures::CalibrateUnlessStopped(bench, *hall.film_field, config.seed, stop_requested);
  if (!hall.calibration) return rig::MakeError(rig::ErrorCode::kInterrupted, "interrupted");
  hall.calibration->set_field_fidelity(hall.field_fidelity);
  return {};
}

}  // namespace hilrig::host
