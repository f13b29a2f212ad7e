// The two on-disk caches of a scene's setup, beside the reference cache: tabulated field maps
// (DIR/field_maps) and DUT calibrations (DIR/calibrations), shared by `hilrig run` and
// `hilrig bench`. Both are keyed on the executable's bytes, so when this executable cannot name
// itself they are off, said once on `notes`, and every setup is done in full as without them.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "host/cache/calibration_store.h"
#include "host/cache/field_map_store.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

struct SetupCaches {
  std::unique_ptr<FileFieldMapStore> field_maps;
  std::unique_ptr<FileCalibrationStore> calibrations;
  // The films of this process's runs, over `field_maps` (in memory only when that is off).
  std::unique_ptr<FilmFieldModels> film_models;
};

// Under `root`, or DefaultReferenceCacheDir() when it is empty.
SetupCaches MakeSetupCaches(const std::optional<std::string>& root, std::ostream& notes);

// A tactile scene's film (BuildFilmField through `film_models`) and DUT calibration
// (CalibrateThroughStore through `calibrations`), each read from its cache when it holds it and
// made and kept when not: the one setup of `hilrig run` and `hilrig bench`. Null stores make
// both; a scene without pads needs neither. A calibration's failure reads "tactile calibration:
// ...".
rig::Result<void> SetUpTactile(const proto::Scenario& spec, ScenarioConfig& config,
                               FilmFieldModels* film_models,
                               const FileCalibrationStore* calibrations,
                               const std::atomic<bool>* stop_requested);

}  // namespace hilrig::host
