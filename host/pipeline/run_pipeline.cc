#include "host/pipeline/run_pipeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <utility>
#include <variant>

#include "host/cache/setup_caches.h"
#include "host/replay/background_run_log.h"
#include "host/replay/dut_traffic_log.h"
#include "host/report/run_folder.h"
#include "host/report/run_log.h"
#include "host/report/run_plots.h"
#include "host/report/stop_reason.h"
#include "host/scenario/field_path.h"
#include "host/scenario/output_size.h"
#include "host/scenario/reference_trajectory.h"
#include "host/scenario/scenario_loader.h"
#include "host/scenario/timeline_events.h"
#include "host/trace/trace_capture.h"
#include "rig/file_io.h"
#include "rig/realtime_scheduling.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

// The spec as loaded (or given) and resolved; every failure here is the spec's.
struct ResolvedSpec {
  proto::Scenario spec;
  ScenarioConfig config;
};

// The run's trace.csv and can.log. They are written from inside the stepping loop, whose wall
// time is the run's real-time factor: rig::OutputFile buffers 1 MiB of them between write system
// calls.
struct RunFiles {
  RunOutputFolder folder;
  std::unique_ptr<rig::OutputFile> trace;
  std::unique_ptr<rig::OutputFile> can_log;
  std::unique_ptr<rig::OutputFile> log_file;  // run.mcap, unless the request turned it off
  // The trace and the DUT's traffic into it, on the log's own thread.
  std::unique_ptr<BackgroundRunLog> log;
};

// The timeline's events as the plots mark them and the log carries them.
std::vector<PlotMarker> EventMarkers(const ScenarioConfig& config) {
  std::vector<PlotMarker> markers;
  for (TimelineEvent& event : TimelineEvents(config)) {
    markers.push_back({event.at_s, std::move(event.label)});
  }
  return markers;
}

// The reference the runner hands the DUT, sampled evenly over the run (both ends included): a
// path every 10 ms, coarser for runs past 20 s, so the one message stays small however long the
// run.
std::vector<ReferencePose> ReferencePathOf(const ScenarioConfig& config) {
  constexpr std::size_t kMaxPoses = 2000;
  constexpr double kFinestStepS = 0.01;
  const ReferenceTrajectory reference(config.initial_reference, config.setpoints);
  const double duration_s = std::max(config.duration_s, 0.0);
  const std::size_t count = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(duration_s / kFinestStepS)) + 1, 2, kMaxPoses);
  std::vector<ReferencePose> path;
  path.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const ReferenceSample sample =
        reference.Evaluate(duration_s * static_cast<double>(i) / static_cast<double>(count - 1));
    path.push_back({sample.position_m, sample.yaw_rad});
  }
  return path;
}

RunLogScene LogSceneOf(const ScenarioConfig& config) {
  RunLogScene scene;
  scene.grasp = config.gripper.enabled;
  scene.pads = config.hall_sensors.tactile_enabled;
  scene.events = EventMarkers(config);
  scene.reference_path = ReferencePathOf(config);
  scene.envelopes = config.envelopes;
  return scene;
}

rig::Result<RunFiles> OpenRunFiles(const fs::path& out_dir, const std::string& scenario,
                                   const std::string& spec_path) {
  // Locked, and reading "incomplete" until the final report replaces it.
  auto folder = RunOutputFolder::Claim(out_dir.string(), scenario, spec_path);
  if (!folder) return folder.error();
  auto trace = rig::OutputFile::Create((out_dir / "trace.csv").string());
  if (!trace) return trace.error();
  auto can_log = rig::OutputFile::Create((out_dir / "can.log").string());
  if (!can_log) return can_log.error();
  return RunFiles{std::move(folder).value(), std::move(trace).value(), std::move(can_log).value(),
                  nullptr, nullptr};
}

// run.mcap with the DUT's traffic and what a replay needs to rebuild the DUT.
rig::Result<void> OpenRunLog(RunFiles& files, const fs::path& out_dir, const ResolvedSpec& run,
                             const std::string& spec_directory, bool realtime) {
  auto file = rig::OutputFile::Create((out_dir / kRunLogFile).string());
  if (!file) return file.error();
  files.log_file = std::move(file).value();
  auto log = RunLogWriter::Open(files.log_file->stream(), LogSceneOf(run.config));
  if (!log) return rig::InContext(kRunLogFile + std::string(": "), log.error());
  proto::RunRecording recording;
  *recording.mutable_spec() = run.spec;
  std::error_code error;
  const fs::path directory = fs::absolute(spec_directory.empty() ? "." : spec_directory, error);
  recording.set_spec_directory(error ? spec_directory : directory.string());
  recording.set_seed(run.config.seed);
  recording.set_realtime(realtime);
  auto traffic = DutTrafficLog::Open(*log.value(), recording);
  if (!traffic) return rig::InContext(kRunLogFile + std::string(": "), traffic.error());
  files.log =
      std::make_unique<BackgroundRunLog>(std::move(log).value(), std::move(traffic).value());
  return {};
}

rig::Result<void> FinishRunFiles(RunFiles& files, const proto::Report& report,
                                 const fs::path& out_dir, std::vector<std::string>& written) {
  if (auto closed = files.trace->Close(); !closed) return closed.error();
  if (auto closed = files.can_log->Close(); !closed) return closed.error();
  if (files.log) {
    if (auto closed = files.log->Close(); !closed) {
      return rig::InContext(kRunLogFile + std::string(": "), closed.error());
    }
    if (auto closed = files.log_file->Close(); !closed) return closed.error();
    written.push_back((out_dir / kRunLogFile).string());
  }
  if (auto finished = files.folder.Finish(report); !finished) return finished.error();
  for (const char* file : {"trace.csv", "can.log", "junit.xml", "report.json", "index.html"}) {
    written.push_back((out_dir / file).string());
  }
  // A MAVLink DUT's telemetry log (host/linked_dut/mavlink_dut_link.h).
  if (std::error_code error; fs::is_regular_file(out_dir / "mavlink.tlog", error)) {
    written.push_back((out_dir / "mavlink.tlog").string());
  }
  return {};
}

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

// A run made ready to fly: its spec resolved, its folder claimed, its tactile sensors set up and
// its reference (made or read) open for the comparison. It stays in place while the run flies:
// the run's sinks point into it.
struct PreparedRun {
  ResolvedSpec run;
  std::string name;  // the spec's path, else its name: what messages about the run start with
  std::optional<RunFiles> files;
  bool compare = false;
  rig::Result<std::unique_ptr<FidelityComparison>> comparison{nullptr};
  PlottedTrace plotted;
  std::int64_t setup_start_ns = 0;
  std::int64_t reference_ns = 0;  // making or reading the reference: no part of the set-up time
};

using Prepared = std::variant<std::unique_ptr<PreparedRun>, RunError>;

// Loads, resolves and checks the spec, claims the folder, sets up the tactile sensors and starts
// the comparison. The errors are the spec's, the output's or the set-up's (kInterrupted on a
// stop request).
Prepared Prepare(const RunRequest& request, const RunSeams& seams) {
  const std::string spec_directory = !request.spec_directory.empty()
                                         ? request.spec_directory
                                         : fs::path(request.spec_path).parent_path().string();
  auto prepared = std::make_unique<PreparedRun>();
  prepared->setup_start_ns = seams.wall_clock->NowNs();
  auto resolved = LoadAndResolve(request, spec_directory);
  if (!resolved) return RunError{RunFailure::kBadSpec, resolved.error().message};
  ResolvedSpec& run = prepared->run = std::move(resolved).value();
  prepared->name = request.spec_path.empty() ? run.spec.name() : request.spec_path;
  if (const auto warning =
          OutputSizeWarning(run.config, request.run_log && request.out_dir.has_value());
      warning && seams.notes != nullptr) {
    *seams.notes << prepared->name << ": warning: this run " << *warning << "\n";
  }
  if (request.out_dir) {
    auto opened = OpenRunFiles(*request.out_dir, run.spec.name(), request.spec_path);
    if (!opened) return RunError{RunFailure::kOutput, opened.error().message};
    prepared->files.emplace(std::move(opened).value());
    if (request.run_log) {
      if (auto log = OpenRunLog(*prepared->files, *request.out_dir, run, spec_directory,
                                seams.realtime_clock != nullptr);
          !log) {
        return RunError{RunFailure::kOutput, log.error().message};
      }
    }
  }
  if (auto set_up = SetUpTactile(run.spec, run.config, request.film_models, request.calibrations,
                                 seams.stop_requested);
      !set_up) {
    const RunFailure failure = set_up.error().code == rig::ErrorCode::kInterrupted
                                   ? RunFailure::kInterrupted
                                   : RunFailure::kSetUp;
    return RunError{failure, prepared->name + ": " + set_up.error().message};
  }
  // The comparison with the reference reads the reference as the run goes: neither trace is kept.
  prepared->compare = request.reference != nullptr;
  const std::int64_t reference_start_ns = seams.wall_clock->NowNs();
  if (prepared->compare) {
    prepared->comparison = StartComparison(request, seams, run, spec_directory);
  }
  prepared->reference_ns = seams.wall_clock->NowNs() - reference_start_ns;
  return prepared;
}

// The sinks of a prepared run: its files, its plots' decimated series (the same size however
// long the run), the comparison, and how far the run got.
RunSinks SinksOf(PreparedRun& prepared, const RunSeams& seams) {
  RunSinks sinks;
  std::optional<RunFiles>& files = prepared.files;
  if (files) {
    sinks.trace_csv = &files->trace->stream();
    sinks.can_log = &files->can_log->stream();
  }
  sinks.progress = seams.notes;
  FidelityComparison* const compared =
      prepared.comparison ? prepared.comparison.value().get() : nullptr;
  if (files || compared != nullptr) {
    PlottedTrace* const plotted = files ? &prepared.plotted : nullptr;
    BackgroundRunLog* const log = files ? files->log.get() : nullptr;
    sinks.trace_sample = [plotted, compared, log](const TraceSample& sample) {
      if (plotted != nullptr) plotted->Add(sample);
      if (compared != nullptr) compared->Add(sample);
      if (log != nullptr) log->Add(sample);
    };
  }
  // A real-time loop does not spend its period on rewriting the report (about 0.4 ms, up to 3):
  // its folder says "incomplete" without how far.
  if (files && seams.realtime_clock == nullptr && seams.notes != nullptr) {
    RunOutputFolder* const folder = &files->folder;
    std::ostream* const notes = seams.notes;
    sinks.flushed = [folder, notes](double simulated_s) { folder->Reached(simulated_s, *notes); };
  }
  return sinks;
}

// Flies the prepared run to its end (or its stop) and reports it, under SCHED_FIFO in real time
// when asked.
RunOutcome Fly(PreparedRun& prepared, const RunRequest& request, const RunSeams& seams) {
  const bool realtime = seams.realtime_clock != nullptr;
  std::optional<rig::ScopedFifoScheduling> scheduling;
  if (realtime && request.realtime_priority > 0) {
    // Before the run starts its dut process, which inherits the policy.
    scheduling.emplace(request.realtime_priority);
    if (!scheduling->granted() && seams.notes != nullptr) {
      *seams.notes << prepared.name << ": " << scheduling->description()
                   << "; the timing figures are the default scheduler's\n";
    }
  }
  RunControl control;
  control.wall_clock = seams.wall_clock;
  control.stop_requested = seams.stop_requested;
  control.dut_factory = request.dut_factory;
  control.realtime_clock = seams.realtime_clock;
  control.run_folder = request.out_dir.value_or("");
  control.dut_traffic = prepared.files ? prepared.files->log.get() : nullptr;
  RunOutcome outcome;
  outcome.report = RunScenario(prepared.run.config, SinksOf(prepared, seams), control);
  if (realtime) {
    outcome.report.mutable_timing()->set_scheduling(
        scheduling ? scheduling->description() : "default scheduler (--rt-priority 0)");
  }
  scheduling.reset();  // writing files and plots is no real-time work
  if (!request.spec_path.empty()) outcome.report.set_spec_file(request.spec_path);
  proto::Provenance& provenance = *outcome.report.mutable_provenance() = request.provenance;
  for (const auto& [path, value] : request.overrides) {
    proto::SpecOverride* applied = provenance.add_overrides();
    applied->set_path(path);
    applied->set_value(value);
  }
  // Calibrating at start and tabulating field maps happen before the first tick; the real-time
  // factor is the stepping loop's, and this is the rest.
  outcome.report.set_setup_s(static_cast<double>(seams.wall_clock->NowNs() -
                                                 prepared.setup_start_ns - prepared.reference_ns) /
                                 1e9 -
                             outcome.report.wall_s());
  return outcome;
}

RunPlotScene PlotSceneOf(const ScenarioConfig& config) {
  RunPlotScene scene;
  scene.envelopes = config.envelopes;
  scene.grasp = config.gripper.enabled;
  scene.pads = config.hall_sensors.tactile_enabled;
  scene.events = EventMarkers(config);
  return scene;
}

// The run's plots, its fidelity error and its finished folder; the verdict. Fails only on output.
std::optional<RunError> Publish(PreparedRun& prepared, const RunRequest& request,
                                const RunSeams& seams, RunOutcome& outcome) {
  if (prepared.files) {
    auto plots =
        WriteRunPlots(prepared.plotted, PlotSceneOf(prepared.run.config), *request.out_dir);
    if (!plots) return RunError{RunFailure::kOutput, plots.error().message};
    for (const std::string& plot : plots.value()) {
      outcome.report.add_plots(plot);
      outcome.files_written.push_back((fs::path(*request.out_dir) / plot).string());
    }
  }
  if (prepared.compare && RunCompleted(outcome.report)) {
    FidelityComparison* const compared =
        prepared.comparison ? prepared.comparison.value().get() : nullptr;
    SetFidelityError(compared != nullptr
                         ? compared->Finish()
                         : rig::Result<proto::FidelityError>(prepared.comparison.error()),
                     seams, prepared.name, outcome);
  }
  if (prepared.files) {
    if (auto finished = FinishRunFiles(*prepared.files, outcome.report, *request.out_dir,
                                       outcome.files_written);
        !finished) {
      return RunError{RunFailure::kOutput, finished.error().message};
    }
  }
  outcome.verdict = outcome.report.passed() ? RunVerdict::kPass : RunVerdict::kCheckFailed;
  return std::nullopt;
}

}  // namespace

RunPipelineResult RunPipeline(const RunRequest& request, const RunSeams& seams) {
  Prepared prepared = Prepare(request, seams);
  if (RunError* error = std::get_if<RunError>(&prepared)) return std::move(*error);
  PreparedRun& run = *std::get<std::unique_ptr<PreparedRun>>(prepared);
  RunOutcome outcome = Fly(run, request, seams);
  if (std::optional<RunError> error = Publish(run, request, seams, outcome)) {
    return std::move(*error);
  }
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
