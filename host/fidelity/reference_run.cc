#include "host/fidelity/reference_run.h"

#include <utility>
#include <vector>

#include "host/fidelity/trace_comparison.h"
#include "host/report/stop_reason.h"
#include "host/scenario/scenario_validation.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

rig::Result<ScenarioConfig> ResolveChecked(const proto::Scenario& spec,
                                           const std::string& spec_directory,
                                           std::optional<std::uint64_t> seed) {
  const std::vector<FieldProblem> problems = ValidateScenario(spec);
  if (!problems.empty()) {
    return rig::MakeError(spec.name() + ": " + problems.front().field_path + ": " +
                          problems.front().message);
  }
  if (spec.models().tactile().enabled() && spec.models().tactile().has_field_fidelity()) {
    // Parsed, not built: building a field map here would tabulate it once more per run.
    if (auto film = ParseFilmFidelity(spec.models().tactile().field_fidelity()); !film) {
      return rig::MakeError(spec.name() +
                            ": models.tactile.field_fidelity: " + film.error().message);
    }
  }
  return ResolveScenario(spec, seed, spec_directory);
}

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
    if (std::optional<CachedReference> cached =
            source.cache->Load(key, CompletedRunTraceSamples(reference_config.value()))) {
      return ReferenceRun{std::move(*cached), true};
    }
  }
  if (source.notes != nullptr) {
    *source.notes << spec.name() << ": running the reference (" << FidelityLabel(source.fidelity)
                  << ")"
                  << (source.cache != nullptr ? ", kept in " + source.cache->directory() : "")
                  << std::endl;
  }
  RunControl lockstep_in_process;
  lockstep_in_process.wall_clock = control.wall_clock;
  lockstep_in_process.stop_requested = control.stop_requested;
  CapturedRun reference_run = RunCaptured(reference_config.value(), lockstep_in_process);
  if (!RunCompleted(reference_run.report)) {
    return StoppedShortError("the reference run stopped short: ", reference_run.report);
  }
  ReferenceRun reference{{std::move(reference_run.trace), reference_run.report.wall_s()}, false};
  if (source.cache != nullptr) {
    // A cache that cannot be written costs the next run time, not this run its answer.
    if (auto stored = source.cache->Store(key, reference.run); !stored && source.notes != nullptr) {
      *source.notes << spec.name() << ": reference not cached: " << stored.error().message << "\n";
    }
  }
  return reference;
}

rig::Result<proto::FidelityError> FidelityErrorOf(
    const ScenarioConfig& chosen, const CapturedTrace& chosen_trace, const proto::Scenario& spec,
    const std::string& spec_directory, const ReferenceSource& source, const RunControl& control) {
  auto reference = ReferenceFor(chosen, spec, spec_directory, source, control);
  if (!reference) return reference.error();
  const ErrorMetrics errors = CompareTraces(chosen_trace, reference.value().run.trace);
  proto::FidelityError result;
  result.set_reference_fidelity(FidelityLabel(source.fidelity));
  result.set_reference_cached(reference.value().from_cache);
  result.set_reference_wall_s(reference.value().run.wall_s);
  result.set_samples_compared(errors.samples_compared);
  result.set_grasp_force_rms_n(errors.grasp_force_rms_n);
  result.set_grasp_force_max_n(errors.grasp_force_max_n);
  result.set_load_rms_n(errors.load_rms_n);
  result.set_load_max_n(errors.load_max_n);
  result.set_position_rms_m(errors.position_rms_m);
  result.set_position_max_m(errors.position_max_m);
  return result;
}

}  // namespace hilrig::host
