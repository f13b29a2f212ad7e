// A run's reference and its fidelity error: the scene run again at a tight fidelity (with the
// run's seed and DUT calibration, in process and in lockstep), taken from the reference cache
// when it holds it, and the run's trace compared with it. The reference is made first (written
// to its cache entry as it runs) and the run is compared with it as the run goes, reading the
// entry a block at a time: memory does not grow with the simulated duration. Also the resolution
// both a reference and the work-precision sweep need: a spec validated, its field fidelity parsed,
// resolved. Nothing here reads a clock: the wall clock comes in with RunControl.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "host/cache/reference_cache.h"
#include "host/fidelity/fidelity_choice.h"
#include "host/fidelity/trace_comparison.h"
#include "host/runner/runner.h"
#include "host/scenario/checked_resolve.h"
#include "host/scenario/scenario_config.h"
#include "host/trace/trace_capture.h"
#include "proto/calibration.pb.h"
#include "proto/report.pb.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// The same, sharing `calibration` (the DUT is flashed once for every run).
rig::Result<ScenarioConfig> ResolveWithCalibration(
    const proto::Scenario& spec, const std::string& spec_directory, std::uint64_t seed,
    const std::optional<proto::Calibration>& calibration);

struct CapturedRun {
  proto::Report report;
  CapturedTrace trace;
};

// One run with its trace kept in memory (no files).
CapturedRun RunCaptured(const ScenarioConfig& config, const RunControl& control);

// Where a run's reference comes from: the fidelity it is run at, and optionally a cache that keeps
// reference traces between runs (keyed with `code_identity`, see host/cache/reference_cache.h).
struct ReferenceSource {
  FidelityChoice fidelity;
  const ReferenceCache* cache = nullptr;
  std::string code_identity;      // required with a cache
  std::ostream* notes = nullptr;  // optional: a line when the reference has to be run
};

// The reference run of `chosen`'s scene: `spec` at `source.fidelity`, with chosen's seed and
// chosen's DUT calibration, always with the in-process DUT in lockstep (the reference is a
// question about models, not about the link). Taken from the cache when there, else run, its
// trace written to its cache entry as it goes (to a temporary file when no cache keeps it), and
// read back from there. An error when the reference spec is invalid (e.g. an unknown field
// fidelity), the reference run stopped short of its duration, or its trace could not be written.
struct ReferenceRun {
  ReferenceReader trace;
  bool from_cache = false;
};
rig::Result<ReferenceRun> ReferenceFor(const ScenarioConfig& chosen, const proto::Scenario& spec,
                                       const std::string& spec_directory,
                                       const ReferenceSource& source, const RunControl& control);

// A run compared with its reference as it goes: Add every trace sample of the run, then Finish.
class FidelityComparison {
 public:
  // The reference of `chosen`'s scene made or read (ReferenceFor's errors), before the run.
  static rig::Result<std::unique_ptr<FidelityComparison>> Start(const ScenarioConfig& chosen,
                                                                const proto::Scenario& spec,
                                                                const std::string& spec_directory,
                                                                const ReferenceSource& source,
                                                                const RunControl& control);

  void Add(const TraceSample& sample) { comparison_.AddRun(ComparedColumnsOf(sample)); }
  void Add(const ComparedSample& sample) { comparison_.AddRun(sample); }
  // After a completed run: its error against the reference, or why the reference could not be
  // read through (its file cut or changed since it was checked).
  rig::Result<proto::FidelityError> Finish();

 private:
  FidelityComparison(ReferenceRun reference, std::string reference_fidelity);

  ReferenceRun reference_;
  std::string reference_fidelity_;
  TraceComparison comparison_;
};

// The error of a completed run's trace against the reference of its scene.
rig::Result<proto::FidelityError> FidelityErrorOf(
    const ScenarioConfig& chosen, const CapturedTrace& chosen_trace, const proto::Scenario& spec,
    const std::string& spec_directory, const ReferenceSource& source, const RunControl& control);

}  // namespace hilrig::host
