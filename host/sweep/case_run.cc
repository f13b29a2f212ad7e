#include "host/sweep/case_run.h"

#include <cstdio>
#include <filesystem>

#include "host/pipeline/run_pipeline.h"

namespace hilrig::host {
namespace {

using Outcome = proto::SweepCaseResult::Outcome;

proto::SweepCaseResult Row(const LoadedSweep& sweep, const SweepCase& sweep_case) {
  proto::SweepCaseResult row;
  row.set_index(sweep_case.index);
  row.set_scenario(sweep.scenarios[sweep_case.scenario].spec.name());
  row.set_seed(sweep_case.seed);
  for (const double value : sweep_case.values) row.add_value(value);
  return row;
}

Outcome OutcomeOf(const RunOutcome& run) {
  const proto::StopReason stop = run.report.stop_kind();
  if (stop != proto::STOP_COMPLETED && stop != proto::STOP_ABORTED)
    return proto::SweepCaseResult::STOPPED;
  return run.verdict == RunVerdict::kPass ? proto::SweepCaseResult::PASSED
                                          : proto::SweepCaseResult::FAILED;
}

void Record(const RunOutcome& run, proto::SweepCaseResult& row) {
  row.set_outcome(OutcomeOf(run));
  if (row.outcome() == proto::SweepCaseResult::STOPPED) row.set_detail(run.report.stop_reason());
  for (const proto::EnvelopeResult& envelope : run.report.envelopes()) {
    proto::SweepCaseResult::Envelope* kept = row.add_envelope();
    kept->set_name(envelope.name());
    kept->set_met(envelope.meets_expectation());
    kept->set_worst(envelope.worst_value());
    kept->set_margin(envelope.margin());
  }
  row.set_real_time_factor(run.report.real_time_factor());
  row.set_wall_s(run.report.wall_s());
}

RunPipelineResult Run(const LoadedSweep& sweep, const SweepCase& sweep_case,
                      const proto::Scenario& scenario, const CaseRunSetup& setup,
                      std::optional<std::string> out_dir) {
  RunRequest request;
  const SweepScenario& source = sweep.scenarios[sweep_case.scenario];
  request.spec_path = source.path;
  request.spec = &scenario;
  request.spec_directory = std::filesystem::path(source.path).parent_path().string();
  request.out_dir = std::move(out_dir);
  request.film_models = setup.film_models;
  request.calibrations = setup.calibrations;
  RunSeams seams;
  seams.wall_clock = setup.wall_clock;
  seams.stop_requested = setup.stop_requested;
  return RunPipeline(request, seams);
}

}  // namespace

std::string CaseFolder(const std::string& runs_dir, std::uint64_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "case-%07llu", static_cast<unsigned long long>(index));
  return (std::filesystem::path(runs_dir) / name).string();
}

std::optional<proto::SweepCaseResult> RunCase(const LoadedSweep& sweep, const SweepCase& sweep_case,
                                              const CaseRunSetup& setup) {
  proto::SweepCaseResult row = Row(sweep, sweep_case);
  auto scenario = CaseScenario(sweep, sweep_case);
  if (!scenario) {
    row.set_outcome(proto::SweepCaseResult::INVALID);
    row.set_detail(scenario.error().message);
    return row;
  }
  const bool keep = setup.runs_dir && setup.keep_all_runs;
  std::optional<std::string> folder;
  if (keep) folder = CaseFolder(*setup.runs_dir, sweep_case.index);
  RunPipelineResult result = Run(sweep, sweep_case, scenario.value(), setup, folder);
  if (const auto* error = std::get_if<RunError>(&result)) {
    if (error->failure == RunFailure::kInterrupted) return std::nullopt;
    row.set_outcome(error->failure == RunFailure::kBadSpec ? proto::SweepCaseResult::INVALID
                                                           : proto::SweepCaseResult::SET_UP_FAILED);
    row.set_detail(error->message);
    return row;
  }
  const RunOutcome& run = std::get<RunOutcome>(result);
  if (run.report.stop_kind() == proto::STOP_INTERRUPTED) return std::nullopt;
  Record(run, row);
  if (row.outcome() != proto::SweepCaseResult::PASSED && setup.runs_dir && !keep) {
    // The same run again, into its folder: what failed, with its trace and CAN log.
    const RunPipelineResult kept = Run(sweep, sweep_case, scenario.value(), setup,
                                       CaseFolder(*setup.runs_dir, sweep_case.index));
    if (const auto* error = std::get_if<RunError>(&kept)) {
      row.set_detail(row.detail() + (row.detail().empty() ? "" : "; ") +
                     "its files were not kept: " + error->message);
    }
  }
  return row;
}

}  // namespace hilrig::host
