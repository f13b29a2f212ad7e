// One scenario run from its spec to its output folder, as `hilrig run` makes it: load and validate
// the spec, resolve it, set up its film and DUT calibration (through the setup caches), make or
// read the scene's reference, run it compared with that reference as it goes, and write
// report.json, junit.xml, trace.csv, can.log and the plots. The command line only parses arguments
// and prints the outcome; the bench's run of a scene as shipped is the same pipeline without files.
// Time, the stop request and the notes stream are injected.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "host/cache/calibration_store.h"
#include "host/cache/reference_cache.h"
#include "host/fidelity/reference_run.h"
#include "host/runner/runner.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "proto/report.pb.h"
#include "proto/scenario.pb.h"
#include "rig/clock.h"

namespace hilrig::host {

struct RunRequest {
  // Where the spec is read from; it names the run in errors and in the report (empty: the
  // scene's name does). With `spec` set the spec is not read again.
  std::string spec_path;
  const proto::Scenario* spec = nullptr;  // already loaded; validated all the same
  std::string spec_directory;             // relative paths in the spec; unset: spec_path's folder
  // The folder the run's files go to; unset: nothing is written, only the report is returned.
  std::optional<std::string> out_dir;
  bool run_log = true;  // with out_dir: write run.mcap (host/report/run_log.h) beside the trace
  std::optional<std::uint64_t> seed;  // unset: the spec's own
  // Numbers of the spec set by field path before it is validated (`hilrig run --set`, a sweep
  // case's reproduction), in order; a path or value the spec refuses is a bad spec.
  std::vector<std::pair<std::string, double>> overrides;
  // Set: only the scene's first duration_s seconds run (TruncatedTo: later timeline entries and
  // envelopes that open later are left out); unset, or longer than the scene: all of it.
  std::optional<double> duration_s;
  DutFactory dut_factory;                  // unset: the DUT in this process
  int realtime_priority = 0;               // SCHED_FIFO priority of a real-time run; 0: default
  FilmFieldModels* film_models = nullptr;  // films shared between runs (null: built per run)
  const FileCalibrationStore* calibrations = nullptr;  // calibrations kept between runs
  const ReferenceSource* reference = nullptr;          // unset: no comparison with a reference
  // The build and command that asked for the run, copied into the report; the overrides above are
  // added to it as they are applied.
  proto::Provenance provenance;
};

// What the pipeline does not own: the clocks, the stop request and where its notes go.
struct RunSeams {
  const rig::Clock* wall_clock = nullptr;  // required: times the set-up and the run
  // Set: the run is paced in real time by this clock (usually the same SteadyClock as
  // wall_clock); null: lockstep.
  const rig::PacingClock* realtime_clock = nullptr;
  const std::atomic<bool>* stop_requested = nullptr;
  // Warnings and progress (a reference being run, a cache that cannot be written, a refused
  // real-time priority, why a run has no fidelity error); null: none.
  std::ostream* notes = nullptr;
};

enum class RunVerdict { kPass, kCheckFailed };

struct RunOutcome {
  proto::Report report;
  RunVerdict verdict = RunVerdict::kCheckFailed;
  // Why a completed run's report has no fidelity error although a reference was asked for (the
  // reference could not be made); unset otherwise. A run that did not complete is not compared.
  std::optional<std::string> no_fidelity_error;
  std::vector<std::string> files_written;  // paths, in the order they were finished
};

enum class RunFailure {
  kBadSpec,  // the spec cannot be read or is not valid: nothing is written
  kSetUp,    // the film or the DUT's calibration could not be made
  // A stop request ended the set-up (a calibration, a field map's tabulation) before the run's
  // first tick: the run was interrupted, its input is not at fault.
  kInterrupted,
  kOutput,  // the output folder or one of its files could not be written
};

struct RunError {
  RunFailure failure;
  std::string message;  // names the path and the cause
};

using RunPipelineResult = std::variant<RunOutcome, RunError>;

RunPipelineResult RunPipeline(const RunRequest& request, const RunSeams& seams);

// The reference every run of one command compares with, and the cache that keeps it. Without the
// executable's identity the cache is off (said on `notes`) and every reference is run.
struct ReferenceSetup {
  std::optional<ReferenceCache> cache;
  ReferenceSource source;
};
std::unique_ptr<ReferenceSetup> MakeReferenceSetup(const std::optional<std::string>& cache_dir,
                                                   std::ostream& notes);

}  // namespace hilrig::host
