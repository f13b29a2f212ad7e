#include "host/bench/calibration_store.h"

#include <string_view>
#include <utility>

namespace hilrig::host {
namespace {

// The folder's bound (CacheFolder): about 1 KB each: a thousand scene and seed variants of one
// build.
constexpr std::size_t kMaxCalibrationEntries = 1000;

constexpr std::string_view kMagic = "HRCAL001";

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
    : folder_(std::move(directory), ".calibration", kMaxCalibrationEntries),
      code_identity_(std::move(code_identity)),
      notes_(notes) {}

std::string FileCalibrationStore::PathOf(const proto::Scenario& spec, std::uint64_t seed) const {
  return folder_.PathOf(CalibrationCacheKey(spec, seed, code_identity_));
}

std::optional<proto::Calibration> FileCalibrationStore::Load(const proto::Scenario& spec,
                                                             std::uint64_t seed) const {
  const std::optional<std::string> bytes =
      folder_.Load(CalibrationCacheKey(spec, seed, code_identity_));
  if (!bytes || !bytes->starts_with(kMagic)) return std::nullopt;
  proto::Calibration calibration;
  // An empty message parses from no bytes; a stored calibration always has its sensors.
  if (!calibration.ParseFromString(bytes->substr(kMagic.size())) ||
      calibration.sensors_size() == 0) {
    return std::nullopt;
  }
  return calibration;
}

void FileCalibrationStore::Store(const proto::Scenario& spec, std::uint64_t seed,
                                 const proto::Calibration& calibration) const {
  SayIfNotKept(folder_.Store(CalibrationCacheKey(spec, seed, code_identity_),
                             std::string(kMagic) + DeterministicBytes(calibration)),
               spec.name() + " calibration", notes_);
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
