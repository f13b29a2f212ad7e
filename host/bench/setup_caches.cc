#include "host/bench/setup_caches.h"

#include <filesystem>

#include "host/bench/reference_cache.h"

namespace hilrig::host {

SetupCaches MakeSetupCaches(const std::optional<std::string>& root, std::ostream& notes) {
  auto identity = ExecutableIdentity();
  if (!identity) {
    notes << "hilrig: field map and calibration caches off (" << identity.error().message << ")\n";
    return {};
  }
  const std::filesystem::path folder = root.value_or(DefaultReferenceCacheDir());
  return {std::make_unique<FileFieldMapStore>((folder / "field_maps").string(), identity.value(),
                                              &notes),
          std::make_unique<FileCalibrationStore>((folder / "calibrations").string(),
                                                 identity.value(), &notes)};
}

}  // namespace hilrig::host
