#include "host/cache/calibration_store.h"

#include <utility>

#include "fixtures/calibration/calibration_file.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {
namespace {

// About 1 KB each, so the bound is a thousand scene and seed variants of one build; an entry is
// read under the cap of the calibration file it stands for.
constexpr CacheFormat kCalibrationFormat{.extension = ".calibration",
                                         .magic = "HRCACHEC",
                                         .legacy_magic = "HRCAL001",
                                         .max_entries = 1000,
                                         .max_entry_bytes = fixtures::kMaxCalibrationFileBytes};

// A stored calibration passes the checks of a calibration file: a message that parses from a cut
// entry can have fewer than six nodes, and the DUT reads six.
rig::Result<proto::Calibration> ParseStoredCalibration(const std::string& content) {
  proto::Calibration calibration;
  if (!calibration.ParseFromString(content)) return rig::MakeError("not a calibration message");
  if (auto valid = fixtures::ValidateCalibration(calibration, "calibration"); !valid) {
    return valid.error();
  }
  return calibration;
}

}  // namespace

std::string CalibrationCacheKey(const proto::Scenario& spec, std::uint64_t seed,
                                const std::string& code_identity) {
  Fnv1a64 hash;
  hash.Add(DeterministicBytes(spec));
  hash.Add(&seed, sizeof(seed));
  hash.Add(code_identity);
  return hash.Hex();
}

FileCalibrationStore::FileCalibrationStore(std::string directory, std::string code_identity,
                                           std::ostream* notes)
    : folder_(std::move(directory), kCalibrationFormat, notes),
      code_identity_(std::move(code_identity)) {}

std::string FileCalibrationStore::PathOf(const proto::Scenario& spec, std::uint64_t seed) const {
  return folder_.PathOf(CalibrationCacheKey(spec, seed, code_identity_));
}

std::optional<proto::Calibration> FileCalibrationStore::Load(const proto::Scenario& spec,
                                                             std::uint64_t seed) const {
  return folder_.Load(CalibrationCacheKey(spec, seed, code_identity_), ParseStoredCalibration);
}

void FileCalibrationStore::Store(const proto::Scenario& spec, std::uint64_t seed,
                                 const proto::Calibration& calibration) const {
  SayIfNotKept(folder_.Store(CalibrationCacheKey(spec, seed, code_identity_),
                             DeterministicBytes(calibration)),
               spec.name() + " calibration", folder_.notes());
}

rig::Result<void> CalibrateThroughStore(const proto::Scenario& spec, ScenarioConfig& config,
                                        const FileCalibrationStore* store,
                                        const std::atomic<bool>* stop_requested) {
  HallSensorConfig& hall = config.hall_sensors;
  if (!hall.tactile_enabled) return {};
  if (!hall.calibration_file.empty()) store = nullptr;
  if (store != nullptr) {
    if (std::optional<proto::Calibration> cached = store->Load(spec, config.seed)) {
      hall.calibration = std::move(*cached);
      return {};
    }
  }
  if (auto calibrated = LoadTactileCalibration(config, stop_requested); !calibrated) {
    return calibrated.error();
  }
  if (store != nullptr && hall.calibration) store->Store(spec, config.seed, *hall.calibration);
  return {};
}

}  // namespace hilrig::host
