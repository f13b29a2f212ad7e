// One case of a sweep run through the run pipeline, as `hilrig run` would run its scenario, and
// reduced to the row the sweep keeps: the outcome, each envelope's worst value and margin, and the
// speed. A run writes no files; a case that fails is run a second time into its own folder (the
// run is deterministic, so the files show the very run that failed), which keeps a 10 000-case
// sweep from filling the disk with the traces of cases that passed.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "host/cache/calibration_store.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/sweep/sweep_cases.h"
#include "proto/sweep.pb.h"
#include "rig/clock.h"

namespace hilrig::host {

struct CaseRunSetup {
  const rig::Clock* wall_clock = nullptr;  // required: times each run
  const std::atomic<bool>* stop_requested = nullptr;
  FilmFieldModels* film_models = nullptr;              // shared by the cases of a shard
  const FileCalibrationStore* calibrations = nullptr;  // shared by every shard (on disk)
  // Where the files of a case go, as DIR/case-NNNNNNN (the case's index); unset: none are kept.
  std::optional<std::string> runs_dir;
  bool keep_all_runs = false;  // every case keeps its files, not only those that failed
};

// Runs `sweep_case`; never fails: whatever goes wrong is the case's outcome and detail.
// Returns nothing when a stop request interrupted it (the case did not finish and is not a row).
std::optional<proto::SweepCaseResult> RunCase(const LoadedSweep& sweep, const SweepCase& sweep_case,
                                              const CaseRunSetup& setup);

// The folder a case's files go to under `runs_dir`.
std::string CaseFolder(const std::string& runs_dir, std::uint64_t index);

}  // namespace hilrig::host
