// Calibrations kept in files between processes. A scene whose pads run on a tiled film
// (tactile_hover: tiles:8) spends most of its setup calibrating the DUT against that film at
// start (0.7-1 s; a field map's scenes calibrate in milliseconds), and the result depends only on
// the spec, the seed and the code. The key hashes the spec's deterministic bytes, the seed and the
// executable's identity: any rebuild, and any edit to the spec (even to a check), is a new key,
// which is coarse but never stale. An entry is checked as a calibration file is (six nodes 1..6,
// finite gains) besides its checksum (cache_files.h): a damaged, cut or foreign entry is a miss,
// said, and the scene is calibrated again; a store that fails only costs the next run the
// calibration, and is said.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "host/cache/cache_files.h"
#include "host/scenario/scenario_config.h"
#include "proto/calibration.pb.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// The key (16 hex digits) of a scene's calibration.
std::string CalibrationCacheKey(const proto::Scenario& spec, std::uint64_t seed,
                                const std::string& code_identity);

class FileCalibrationStore {
 public:
  // `notes` (may be null) hears of entries that could not be used and of stores that failed.
  FileCalibrationStore(std::string directory, std::string code_identity, std::ostream* notes);

  std::optional<proto::Calibration> Load(const proto::Scenario& spec, std::uint64_t seed) const;
  void Store(const proto::Scenario& spec, std::uint64_t seed,
             const proto::Calibration& calibration) const;

  std::string PathOf(const proto::Scenario& spec, std::uint64_t seed) const;

 private:
  CacheFolder folder_;
  std::string code_identity_;
};

// The DUT calibration of `config` (resolved from `spec`): from `store` when it holds one for the
// spec and the config's seed, else calibrated now (LoadTactileCalibration) and stored. A null
// store calibrates every time; a spec that names a calibration file reads that instead. Through
// SetUpTactile (setup_caches.h) `hilrig run` and `hilrig bench` both use it, so a sweep that
// calibrates at the reference field (tiles:64, about 47 s) does it once per build, not per sweep.
// `stop_requested` (may be null) ends a calibration early, as an "interrupted" error (code
// kInterrupted).
rig::Result<void> CalibrateThroughStore(const proto::Scenario& spec, ScenarioConfig& config,
                                        const FileCalibrationStore* store,
                                        const std::atomic<bool>* stop_requested = nullptr);

}  // namespace hilrig::host
