#include "host/pipeline/run_pipeline.h"

#include <filesystem>
#include <functional>
#include <utility>

#include "host/cache/setup_caches.h"
#include "host/report/run_folder.h"
#include "host/report/run_plots.h"
#include "host/report/stop_reason.h"
#include "host/scenario/field_path.h"
#include "host/scenario/output_size.h"
#include "host/scenario/scenario_loader.h"
#include "host/trace/trace_capture.h"
#include "rig/file_io.h"
#include "rig/realtime_scheduling.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// The run's trace.csv and can.log. They are written from inside the stepping loop, whose wall
// time is the run's real-time factor: rig::OutputFile buffers 1 MiB of them between write system
// calls.
struct RunFiles {
  RunOutputFolder folder;
  std::unique_ptr<rig::OutputFile> trace;
  std::unique_ptr<rig::OutputFile> can_log;
};

rig::Result<RunFiles> OpenRunFiles(const fs::path& out_dir, const std::string& scenario,
                                   const std::string& spec_path) {
  // Locked, and reading "incomplete" until the final report replaces it.
  auto folder = RunOutputFolder::Claim(out_dir.string(), scenario, spec_path);
  if (!folder) return folder.error();
  auto trace = rig::OutputFile::Create((out_dir / "trace.csv").string());
  if (!trace) return trace.error();
  auto can_log = rig::OutputFile::Create((out_dir / "can.log").string());
  if (!can_log) return can_log.error();
  return RunFiles{std::move(folder).value(), std::move(trace).value(), std::move(can_log).value()};
}

rig::Result<void> FinishRunFiles(RunFiles& files, const proto::Report& report,
                                 const fs::path& out_dir, std::vector<std::string>& written) {
  if (auto closed = files.trace->Close(); !closed) return closed.error();
  if (auto closed = files.can_log->Close(); !closed) return closed.error();
  if (auto finished = files.folder.Finish(report); !finished) return finished.error();
  for (const char* file : {"trace.csv", "can.log", "junit.xml", "report.json", "index.html"}) {
    written.push_back((out_dir / file).string());
  }
  return {};
}

// The spec as loaded (or given) and resolved; every failure here is the spec's.
struct ResolvedSpec {
  proto::Scenario spec;
  ScenarioConfig config;
};

rig::Result<ResolvedSpec> LoadAndResolve(const RunRequest& request,
                                         const std::string& spec_directory) {
  ResolvedSpec resolved;
  if (request.spec != nullptr) {
    resolved.spec = *request.spec;
  } else {
    auto loaded = LoadScenario(request.spec_path);
    if (!loaded) return loaded.error();
    resolved.spec = std::move(loaded).value();
  }
  for (const auto& [path, value] : request.overrides) {
    auto set = SetNumberAt(resolved.spec, path, value);
    if (!set.ok()) return rig::InContext(resolved.spec.name() + ": --set ", set.error());
  }
  if (request.duration_s && *request.duration_s < resolved.spec.simulation().duration_s()) {
    resolved.spec = TruncatedTo(std::move(resolved.spec), *request.duration_s);
  }
  auto config = ResolveChecked(resolved.spec, spec_directory, request.seed);
  if (!config) return config.error();
  resolved.config = std::move(config).value();
  return resolved;
}

// The run's comparison with its reference, started before the run: the reference made or read
// from its cache, the run then compared as it goes. An error says why there is none.
rig::Result<std::unique_ptr<FidelityComparison>> StartComparison(
    const RunRequest& request, const RunSeams& seams, const ResolvedSpec& resolved,
    const std::string& spec_directory) {
  RunControl reference_control;
  reference_control.wall_clock = seams.wall_clock;
  reference_control.stop_requested = seams.stop_requested;
  return FidelityComparison::Start(resolved.config, resolved.spec, spec_directory,
                                   *request.reference, reference_control);
}

// The fidelity error of a completed run set in the report, or why there is none.
void SetFidelityError(rig::Result<proto::FidelityError> error, const RunSeams& seams,
                      const std::string& run_name, RunOutcome& outcome) {
  // Without a reference the run still has its verdict; the report then has no fidelity error.
  if (error) {
    *outcome.report.mutable_fidelity_error() = std::move(error).value();
    return;
  }
  outcome.no_fidelity_error = error.error().message;
  if (seams.notes != nullptr) {
    *seams.notes << run_name << ": no fidelity error: " << error.error().message << "\n";
  }
}

}  // namespace

RunPipelineResult RunPipeline(const RunRequest& request, const RunSeams& seams) {
  const std::string spec_directory = !request.spec_directory.empty()
                                         ? request.spec_directory
                                         : fs::path(request.spec_path).parent_path().string();
  const std::int64_t setup_start_ns = seams.wall_clock->NowNs();
  auto resolved = LoadAndResolve(request, spec_directory);
  if (!resolved) return RunError{RunFailure::kBadSpec, resolved.error().message};
  ResolvedSpec& run = resolved.value();
  const std::string run_name = request.spec_path.empty() ? run.spec.name() : request.spec_path;
  if (const auto warning = OutputSizeWarning(run.config); warning && seams.notes != nullptr) {
    *seams.notes << run_name << ": warning: this run " << *warning << "\n";
  }
  const bool realtime = seams.realtime_clock != nullptr;

  std::optional<RunFiles> files;
  if (request.out_dir) {
    auto opened = OpenRunFiles(*request.out_dir, run.spec.name(), request.spec_path);
    if (!opened) return RunError{RunFailure::kOutput, opened.error().message};
    files.emplace(std::move(opened).value());
  }
  if (auto set_up = SetUpTactile(run.spec, run.config, request.film_models, request.calibrations,
                                 seams.stop_requested);
      !set_up) {
    const RunFailure failure = set_up.error().code == rig::ErrorCode::kInterrupted
                                   ? RunFailure::kInterrupted
                                   : RunFailure::kSetUp;
    return RunError{failure, run_name + ": " + set_up.error().message};
  }
  // The plots' decimated series stay the same size however long the run, and the comparison with
  // the reference reads the reference as the run goes: neither trace is kept. The reference's own
  // run (with a cold cache) is no part of the run's set-up time.
  const bool compare = request.reference != nullptr;
  const std::int64_t reference_start_ns = seams.wall_clock->NowNs();
  auto comparison = compare ? StartComparison(request, seams, run, spec_directory)
                            : rig::Result<std::unique_ptr<FidelityComparison>>(nullptr);
  const std::int64_t reference_ns = seams.wall_clock->NowNs() - reference_start_ns;
  FidelityComparison* const compared = comparison ? comparison.value().get() : nullptr;
  PlottedTrace plotted;
  RunSinks sinks;
  if (files) {
    sinks.trace_csv = &files->trace->stream();
    sinks.can_log = &files->can_log->stream();
  }
  sinks.progress = seams.notes;
  if (files || compared != nullptr) {
    const bool plot = files.has_value();
    sinks.trace_sample = [&plotted, compared, plot](const TraceSample& sample) {
      if (plot) plotted.Add(sample);
      if (compared != nullptr) compared->Add(sample);
    };
  }
  // A real-time loop does not spend its period on rewriting the report (about 0.4 ms, up to 3):
  // its folder says "incomplete" without how far.
  if (files && !realtime && seams.notes != nullptr) {
    sinks.flushed = [&](double simulated_s) { files->folder.Reached(simulated_s, *seams.notes); };
  }
  std::optional<rig::ScopedFifoScheduling> scheduling;
  if (realtime && request.realtime_priority > 0) {
    // Before the run starts its dut process, which inherits the policy.
    scheduling.emplace(request.realtime_priority);
    if (!scheduling->granted() && seams.notes != nullptr) {
      *seams.notes << run_name << ": " << scheduling->description()
                   << "; the timing figures are the default scheduler's\n";
    }
  }
  RunOutcome outcome;
  outcome.report = RunScenario(
      run.config, sinks,
      {seams.wall_clock, seams.stop_requested, request.dut_factory, seams.realtime_clock});
  if (realtime) {
    outcome.report.mutable_timing()->set_scheduling(
        scheduling ? scheduling->description() : "default scheduler (--rt-priority 0)");
  }
  scheduling.reset();  // writing files and plots is no real-time work
  if (!request.spec_path.empty()) outcome.report.set_spec_file(request.spec_path);
  // Calibrating at start and tabulating field maps happen before the first tick; the real-time
  // factor is the stepping loop's, and this is the rest.
  outcome.report.set_setup_s(
      static_cast<double>(seams.wall_clock->NowNs() - setup_start_ns - reference_ns) / 1e9 -
      outcome.report.wall_s());
  if (files) {
    auto plots =
        WriteRunPlots(plotted, run.config.envelopes, run.config.gripper.enabled, *request.out_dir);
    if (!plots) return RunError{RunFailure::kOutput, plots.error().message};
    for (const std::string& plot : plots.value()) {
      outcome.report.add_plots(plot);
      outcome.files_written.push_back((fs::path(*request.out_dir) / plot).string());
    }
  }
  if (compare && RunCompleted(outcome.report)) {
    SetFidelityError(compared != nullptr ? compared->Finish()
                                         : rig::Result<proto::FidelityError>(comparison.error()),
                     seams, run_name, outcome);
  }
  if (files) {
    if (auto finished =
            FinishRunFiles(*files, outcome.report, *request.out_dir, outcome.files_written);
        !finished) {
      return RunError{RunFailure::kOutput, finished.error().message};
    }
  }
  outcome.verdict = outcome.report.passed() ? RunVerdict::kPass : RunVerdict::kCheckFailed;
  return outcome;
}

std::unique_ptr<ReferenceSetup> MakeReferenceSetup(const std::optional<std::string>& cache_dir,
                                                   std::ostream& notes) {
  auto setup = std::make_unique<ReferenceSetup>();
  setup->source.fidelity = ReferenceFidelity(false);
  setup->source.notes = &notes;
  auto identity = ExecutableIdentity();
  if (identity) {
    setup->cache.emplace(cache_dir.value_or(DefaultReferenceCacheDir()), &notes);
    setup->source.cache = &*setup->cache;
    setup->source.code_identity = identity.value();
  } else {
    notes << "hilrig: reference cache off (" << identity.error().message << ")\n";
  }
  return setup;
}

}  // namespace hilrig::host
