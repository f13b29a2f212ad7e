// Setting up a resolved scene before it runs: the work that can take long (tabulating a film
// field map, running the calibration jigs for up to tens of seconds) and so is not done while a
// spec is resolved (host/scenario), but here, where the caller chooses when, with a stop request
// and, for the field maps, a store that keeps the tables between runs.
#pragma once

#include <atomic>

#include "host/scenario/scenario_config.h"
#include "rig/result.h"

namespace hilrig::host {

class FilmFieldModels;  // host/sensors/tactile/film_field_factory.h

// The DUT's tactile calibration, as the firmware would be flashed with it: read from the spec's
// calibration file, or found by running the calibration jigs on the scene's own sensor models.
// Does nothing when the tactile nodes are off.
// `stop_requested` (may be null) ends a calibration early, as an "interrupted" error (code
// kInterrupted).
rig::Result<void> LoadTactileCalibration(ScenarioConfig& config,
                                         const std::atomic<bool>* stop_requested = nullptr);

// Builds hall_sensors.film_field for its field_fidelity unless the config already has one: the
// model `film_models` holds or builds for the level, or a model built for this config alone when
// it is null (MakeFilmField, which `stop_requested`, may be null, interrupts).
rig::Result<void> BuildFilmField(ScenarioConfig& config, FilmFieldModels* film_models = nullptr,
                                 const std::atomic<bool>* stop_requested = nullptr);

}  // namespace hilrig::host
