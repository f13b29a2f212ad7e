#include "host/fidelity/reference_run.h"

#include <utility>
#include <vector>

#include "host/fidelity/trace_comparison.h"
#include "host/report/stop_reason.h"
#include "host/scenario/scenario_validation.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

rig::Result<ScenarioConfig> ResolveWithCalibration(
    const proto::Scenario& spec, const std::string& spec_directory, std::uint64_t seed,
    const std::optional<proto::Calibration>& calibration) {
  auto config = ResolveChecked(spec, spec_directory, seed);
  if (!config) return config.error();
  config.value().hall_sensors.calibration = calibration;
  return config;
}

CapturedRun RunCaptured(const ScenarioConfig& config, const RunControl& control) {
  CapturedRun run;
  RunSinks sinks;
  sinks.trace_sample = [&run](const TraceSample& sample) { run.trace.Add(sample); };
  run.report = RunScenario(config, sinks, control);
  return run;
}

namespace {

// Where a reference that has to be run is written: its cache entry (then `cached`), else a
// temporary file.
rig::Result<ReferenceWriter> ReferenceWriterFor(const ReferenceSource& source,
                                                const std::string& key, const std::string& scene,
                                                bool& cached) {
  cached = false;
  if (source.cache != nullptr) {
    auto writer = source.cache->Begin(key);
    cached = writer.ok();
    if (writer) return writer;
    // A cache that cannot be written costs the next run time, not this run its answer.
    if (source.notes != nullptr) {
      *source.notes << scene << ": reference not cached: " << writer.error().message << "\n";
    }
  }
  return ReferenceWriter::Unnamed();
}

// Runs the reference, writing its trace as it goes, and opens what it wrote for reading.
rig::Result<ReferenceRun> RunReference(const ScenarioConfig& reference_config,
                                       const std::string& key, const std::string& scene,
                                       const ReferenceSource& source, const RunControl& control) {
  bool cached = false;
  auto writer = ReferenceWriterFor(source, key, scene, cached);
  if (!writer) return rig::InContext("the reference trace cannot be kept: ", writer.error());
  RunControl lockstep_in_process;
  lockstep_in_process.wall_clock = control.wall_clock;
  lockstep_in_process.stop_requested = control.stop_requested;
  RunSinks sinks;
  sinks.trace_sample = [&writer](const TraceSample& sample) {
    writer.value().Add(ComparedColumnsOf(sample));
  };
  const proto::Report report = RunScenario(reference_config, sinks, lockstep_in_process);
  if (!RunCompleted(report)) {
    return StoppedShortError("the reference run stopped short: ", report);
  }
  if (auto finished = writer.value().Finish(report.wall_s()); !finished) {
    return rig::InContext("the reference trace cannot be kept: ", finished.error());
  }
  if (cached) {
    if (auto committed = source.cache->Commit(writer.value());
        !committed && source.notes != nullptr) {
      *source.notes << scene << ": reference not cached: " << committed.error().message << "\n";
    }
  }
  auto entry = writer.value().entry().Reader();
  if (!entry) return entry.error();
  auto trace = ReferenceReader::Open(std::move(entry).value(), std::nullopt);
  if (!trace) return trace.error();
  return ReferenceRun{std::move(trace).value(), false};
}

}  // namespace

rig::Result<ReferenceRun> ReferenceFor(const ScenarioConfig& chosen, const proto::Scenario& spec,
                                       const std::string& spec_directory,
                                       const ReferenceSource& source, const RunControl& control) {
  const proto::Scenario reference_spec = WithFidelity(spec, source.fidelity);
  auto reference_config = ResolveWithCalibration(reference_spec, spec_directory, chosen.seed,
                                                 chosen.hall_sensors.calibration);
  if (!reference_config) return reference_config.error();
  const std::string key =
      source.cache == nullptr
          ? std::string()
          : ReferenceCacheKey(reference_spec, chosen.seed, chosen.hall_sensors.calibration,
                              source.code_identity);
  if (source.cache != nullptr) {
    if (std::optional<ReferenceReader> cached =
            source.cache->Open(key, CompletedRunTraceSamples(reference_config.value()))) {
      return ReferenceRun{std::move(*cached), true};
    }
  }
  if (source.notes != nullptr) {
    *source.notes << spec.name() << ": running the reference (" << FidelityLabel(source.fidelity)
                  << ")"
                  << (source.cache != nullptr ? ", kept in " + source.cache->directory() : "")
                  << std::endl;
  }
  return RunReference(reference_config.value(), key, spec.name(), source, control);
}

rig::Result<std::unique_ptr<FidelityComparison>> FidelityComparison::Start(
    const ScenarioConfig& chosen, const proto::Scenario& spec, const std::string& spec_directory,
    const ReferenceSource& source, const RunControl& control) {
  auto reference = ReferenceFor(chosen, spec, spec_directory, source, control);
  if (!reference) return reference.error();
  return std::unique_ptr<FidelityComparison>(
      new FidelityComparison(std::move(reference).value(), FidelityLabel(source.fidelity)));
}

FidelityComparison::FidelityComparison(ReferenceRun reference, std::string reference_fidelity)
    : reference_(std::move(reference)),
      reference_fidelity_(std::move(reference_fidelity)),
      comparison_([this] { return reference_.trace.Next(); }) {}

rig::Result<proto::FidelityError> FidelityComparison::Finish() {
  const ErrorMetrics errors = comparison_.Finish();
  if (reference_.trace.failure()) return *reference_.trace.failure();
  proto::FidelityError result;
  result.set_reference_fidelity(reference_fidelity_);
  result.set_reference_cached(reference_.from_cache);
  result.set_reference_wall_s(reference_.trace.wall_s());
  result.set_samples_compared(errors.samples_compared);
  result.set_grasp_force_rms_n(errors.grasp_force_rms_n);
  result.set_grasp_force_max_n(errors.grasp_force_max_n);
  result.set_load_rms_n(errors.load_rms_n);
  result.set_load_max_n(errors.load_max_n);
  result.set_position_rms_m(errors.position_rms_m);
  result.set_position_max_m(errors.position_max_m);
  return result;
}

rig::Result<proto::FidelityError> FidelityErrorOf(
    const ScenarioConfig& chosen, const CapturedTrace& chosen_trace, const proto::Scenario& spec,
    const std::string& spec_directory, const ReferenceSource& source, const RunControl& control) {
  auto comparison = FidelityComparison::Start(chosen, spec, spec_directory, source, control);
  if (!comparison) return comparison.error();
  for (std::size_t i = 0; i < chosen_trace.size(); ++i) comparison.value()->Add(chosen_trace.At(i));
  return comparison.value()->Finish();
}

}  // namespace hilrig::host
