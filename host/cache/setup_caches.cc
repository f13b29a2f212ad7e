#include "host/cache/setup_caches.h"

#include <filesystem>

#include "host/cache/reference_cache.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {

SetupCaches MakeSetupCaches(const std::optional<std::string>& root, std::ostream& notes) {
  auto identity = ExecutableIdentity();
  SetupCaches caches;
  if (!identity) {
    notes << "hilrig: field map and calibration caches off (" << identity.error().message << ")\n";
  } else {
    const std::filesystem::path folder = root.value_or(DefaultReferenceCacheDir());
    caches.field_maps = std::make_unique<FileFieldMapStore>((folder / "field_maps").string(),
                                                            identity.value(), &notes);
    caches.calibrations = std::make_unique<FileCalibrationStore>((folder / "calibrations").string(),
                                                                 identity.value(), &notes);
  }
  caches.film_models = std::make_unique<FilmFieldModels>(caches.field_maps.get());
  return caches;
}

rig::Result<void> SetUpTactile(const proto::Scenario& spec, ScenarioConfig& config,
                               FilmFieldModels* film_models,
                               const FileCalibrationStore* calibrations,
                               const std::atomic<bool>* stop_requested) {
  if (auto built = BuildFilmField(config, film_models, stop_requested); !built) {
    return built.error();
  }
  if (auto calibrated = CalibrateThroughStore(spec, config, calibrations, stop_requested);
      !calibrated) {
    return rig::InContext("tactile calibration: ", calibrated.error());
  }
  return {};
}

}  // namespace hilrig::host
