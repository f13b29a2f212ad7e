#include "host/work_precision/work_precision.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <memory>
#include <span>
#include <string_view>
#include <variant>

#include "host/cache/setup_caches.h"
#include "host/pipeline/run_pipeline.h"
#include "host/report/signal_unit.h"
#include "host/report/stop_reason.h"
#include "host/runner/run_statistics.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/setup/scene_setup.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr double kSweepTolerance = 1e-6;
constexpr double kQuickDurationS = 3;

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

double WallPerSimulatedSecond(const proto::Report& report) {
  return report.simulated_s() > 0 ? report.wall_s() / report.simulated_s() : 0.0;
}

bool Interrupted(const RunControl& control) {
  return control.stop_requested != nullptr && control.stop_requested->load();
}

bool CheapToRepeat(const RunResult& run, const SweepOptions& options) {
  return options.timing_repeats > 1 &&
         run.wall_s_per_sim_s * run.simulated_s < options.cheap_run_wall_s;
}

// Times the cheap runs again without sinks (the captured run's trace capture adds to its loop), in
// rounds over all of them: round r times every run once before round r + 1 starts, so a slow
// spell of a shared machine slows every configuration alike instead of deciding one's place on
// the front. Each keeps its fastest: noise on a shared machine only ever adds time. Expensive runs
// keep their captured timing.
void TimeInRounds(const std::vector<ScenarioConfig>& configs, SceneResult& scene,
                  const SweepOptions& options, const RunControl& control) {
  std::vector<double> fastest(scene.runs.size(), std::numeric_limits<double>::infinity());
  for (int round = 0; round < options.timing_repeats; ++round) {
    for (std::size_t i = 0; i < scene.runs.size() && !Interrupted(control); ++i) {
      if (!CheapToRepeat(scene.runs[i], options)) continue;
      const double timed = WallPerSimulatedSecond(RunScenario(configs[i], {}, control));
      fastest[i] = std::min(fastest[i], timed);
      scene.runs[i].timing_runs = round + 1;
    }
  }
  for (std::size_t i = 0; i < scene.runs.size(); ++i) {
    if (std::isfinite(fastest[i])) scene.runs[i].wall_s_per_sim_s = fastest[i];
  }
}

// A signal in newtons: what the force checks and the tightest force envelope are made of.
bool IsForceSignal(proto::Signal signal) { return std::string_view(SignalUnit(signal)) == "N"; }

RunResult Evaluate(const PlannedRun& planned, const ScenarioConfig& config,
                   const CapturedRun& captured, const CapturedTrace& reference) {
  RunResult result;
  result.run = planned;
  result.step_s = static_cast<double>(config.physics_step_ns) / 1e9 / config.plant_substeps;
  result.errors = CompareTraces(captured.trace, reference);
  result.passes_envelopes = captured.report.passed();
  for (const proto::EnvelopeResult& envelope : captured.report.envelopes()) {
    if (envelope.expected() != proto::PASS || envelope.not_evaluated()) continue;
    if (!IsForceSignal(envelope.signal())) continue;
    result.force_check_worst_n.emplace_back(envelope.name(), envelope.worst_value());
  }
  result.stop_reason = captured.report.stop_reason();
  result.simulated_s = captured.report.simulated_s();
  result.wall_s_per_sim_s = WallPerSimulatedSecond(captured.report);
  result.timing_runs = 1;
  return result;
}

std::string RealTimeFactor(double wall_s_per_sim_s) {
  return wall_s_per_sim_s > 0 ? rig::NumberText(1 / wall_s_per_sim_s) : "0";
}

std::string ParetoField(const RunResult& run) {
  std::string out;
  for (ErrorMetric metric : run.pareto) {
    out.append(out.empty() ? "" : ";").append(MetricName(metric));
  }
  if (run.on_joint_front) out.append(out.empty() ? "" : ";").append("all");
  return out.empty() ? "-" : out;
}

std::string MetricUnit(ErrorMetric metric) { return metric == ErrorMetric::kPosition ? "m" : "N"; }

std::string MetricTitle(ErrorMetric metric) {
  switch (metric) {
    case ErrorMetric::kGraspForce:
      return "grasp force";
    case ErrorMetric::kLoad:
      return "vertical load";
    case ErrorMetric::kPosition:
      return "position";
  }
  return "";
}

// The family a run is drawn in: one per integrator, one for the field sweep, the default alone.
std::string FamilyOf(const RunResult& run) {
  switch (run.run.kind) {
    case RunKind::kIntegrator:
      return IntegratorLabel(run.run.fidelity);
    case RunKind::kField:
      return "field fidelity";
    case RunKind::kDefault:
      return "as shipped";
    case RunKind::kEffect:
      return "sensor effect off";
    case RunKind::kReference:
      break;
  }
  return "reference";
}

std::string PointLabel(const RunResult& run) {
  switch (run.run.kind) {
    case RunKind::kIntegrator:
      return "x" + std::to_string(run.run.fidelity.plant_substeps);
    case RunKind::kField:
      return run.run.fidelity.field_fidelity;
    case RunKind::kDefault:
      return "default";
    case RunKind::kEffect:
      return run.run.fidelity.effect_off
                 ? std::string("no ") + SensorEffectName(*run.run.fidelity.effect_off)
                 : "no effect";
    case RunKind::kReference:
      break;
  }
  return "reference";
}

ScatterPlot PlotFor(const SceneResult& scene, ErrorMetric metric) {
  ScatterPlot plot;
  plot.title = scene.scene + ": " + MetricTitle(metric) + " error";
  plot.x_label = "wall time per simulated second (s)";
  plot.y_label = "RMS " + MetricTitle(metric) + " error (" + MetricUnit(metric) + ")";
  for (const RunResult& run : scene.runs) {
    if (run.run.kind == RunKind::kReference) continue;
    const std::string family = FamilyOf(run);
    auto series = std::find_if(plot.series.begin(), plot.series.end(),
                               [&](const ScatterSeries& s) { return s.name == family; });
    if (series == plot.series.end()) {
      plot.series.push_back({family, "", {}});
      series = std::prev(plot.series.end());
    }
    series->points.push_back({run.wall_s_per_sim_s, run.RmsError(metric), PointLabel(run)});
  }
  for (std::size_t index : ParetoFront(scene.runs, metric, scene.tolerance)) {
    plot.front.push_back(
        {scene.runs[index].wall_s_per_sim_s, scene.runs[index].RmsError(metric), ""});
  }
  return plot;
}

const RunResult* DefaultRun(const SceneResult& scene) {
  for (const RunResult& run : scene.runs) {
    if (run.run.kind == RunKind::kDefault) return &run;
  }
  return nullptr;
}

std::string FrontTable(const SceneResult& scene, ErrorMetric metric) {
  char line[256];
  std::snprintf(line, sizeof(line), "%s: %s RMS error (%s), Pareto front\n", scene.scene.c_str(),
                MetricTitle(metric).c_str(), MetricUnit(metric).c_str());
  std::string out = line;
  std::snprintf(line, sizeof(line), "  %-12s %-10s %-10s %-26s %s\n", "wall s/sim s", "error",
                "kind", "run", "envelopes");
  out += line;
  for (std::size_t index : ParetoFront(scene.runs, metric, scene.tolerance)) {
    const RunResult& run = scene.runs[index];
    std::snprintf(line, sizeof(line), "  %-12.4g %-10.3g %-10s %-26s %s\n", run.wall_s_per_sim_s,
                  run.RmsError(metric), RunKindName(run.run.kind).c_str(),
                  FidelityLabel(run.run.fidelity).c_str(), run.passes_envelopes ? "pass" : "FAIL");
    out += line;
  }
  return out;
}

std::string DefaultVerdict(const SceneResult& scene) {
  const RunResult* run = DefaultRun(scene);
  if (run == nullptr) return scene.scene + ": no default run\n";
  std::string on;
  for (ErrorMetric metric : run->pareto)
    on.append(on.empty() ? "" : ", ").append(MetricName(metric));
  std::string out = scene.scene;
  out.append(": the default (").append(FidelityLabel(run->run.fidelity)).append(", ");
  out.append(rig::NumberText(run->wall_s_per_sim_s)).append(" s per simulated s) is ");
  out.append(run->on_joint_front ? "on the joint front (time against all three errors)"
                                 : "NOT on the joint front (time against all three errors)");
  out.append(on.empty() ? ", on no single-error front" : ", on the single-error front for ")
      .append(on)
      .append("; it ");
  out.append(run->passes_envelopes ? "passes" : "does NOT pass").append(" its envelopes");
  if (scene.cut_to_s) {
    out.append(" over the sweep's first ").append(rig::NumberText(*scene.cut_to_s));
    out.append(" s (a check whose window starts later has nothing to judge there)");
  }
  out.append("\n");
  out.append(scene.scene).append(": as shipped (its own noise and seed) the default ");
  if (scene.shipped.passed) {
    out.append("meets every expected verdict\n");
  } else {
    out.append("does NOT meet its expected verdicts (");
    for (const std::string& name : scene.shipped.missed) out.append(name).append(" ");
    out.append("stop: ").append(scene.shipped.stop_reason).append(")\n");
  }
  const RunResult* cheapest = CheapestPassingFrontRun(scene);
  out.append(scene.scene).append(": the cheapest run on the joint front that passes is ");
  if (cheapest == nullptr) return out.append("none\n");
  out.append(FidelityLabel(cheapest->run.fidelity)).append(" (");
  return out.append(rig::NumberText(cheapest->wall_s_per_sim_s)).append(" s per simulated s)\n");
}

}  // namespace

std::string RunKindName(RunKind kind) {
  switch (kind) {
    case RunKind::kReference:
      return "reference";
    case RunKind::kIntegrator:
      return "integrator";
    case RunKind::kField:
      return "field";
    case RunKind::kDefault:
      return "default";
    case RunKind::kEffect:
      return "effect";
  }
  return "unknown";
}

std::vector<PlannedRun> PlanSweep(const FidelityChoice& scene, bool has_film, bool quick,
                                  std::span<const SensorEffect> effects) {
  const std::vector<proto::Integrator> integrators =
      quick ? std::vector<proto::Integrator>{proto::INTEGRATOR_SEMI_IMPLICIT_EULER,
                                             proto::INTEGRATOR_RK4}
            : std::vector<proto::Integrator>{proto::INTEGRATOR_SEMI_IMPLICIT_EULER,
                                             proto::INTEGRATOR_MIDPOINT, proto::INTEGRATOR_RK4,
                                             proto::INTEGRATOR_DORMAND_PRINCE};
  const std::vector<int> substeps = quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 4, 8};
  const std::vector<std::string> fields =
      quick ? std::vector<std::string>{"tiles:8", "map:16"}
            : std::vector<std::string>{"tiles:8", "tiles:16", "tiles:32", "map:16",
                                       "map:32",  "opmap:16", "opmap:32"};
  std::vector<PlannedRun> runs;
  for (proto::Integrator integrator : integrators) {
    for (int steps : substeps) {
      FidelityChoice fidelity = scene;
      fidelity.integrator = integrator;
      fidelity.integrator_tolerance = integrator == proto::INTEGRATOR_DORMAND_PRINCE
                                          ? std::optional<double>(kSweepTolerance)
                                          : std::nullopt;
      fidelity.plant_substeps = steps;
      runs.push_back({RunKind::kIntegrator, fidelity});
    }
  }
  for (const std::string& field : has_film ? fields : std::vector<std::string>{}) {
    FidelityChoice fidelity = scene;
    fidelity.field_fidelity = field;
    runs.push_back({RunKind::kField, fidelity});
  }
  for (SensorEffect effect : effects) {
    FidelityChoice fidelity = scene;
    fidelity.effect_off = effect;
    runs.push_back({RunKind::kEffect, fidelity});
  }
  std::vector<PlannedRun> unique;
  for (const PlannedRun& run : runs) {
    if (run.fidelity == scene) continue;
    const auto seen = [&](const PlannedRun& kept) { return kept.fidelity == run.fidelity; };
    if (std::none_of(unique.begin(), unique.end(), seen)) unique.push_back(run);
  }
  unique.push_back({RunKind::kDefault, scene});
  return unique;
}

std::string MetricName(ErrorMetric metric) {
  switch (metric) {
    case ErrorMetric::kGraspForce:
      return "grasp_force";
    case ErrorMetric::kLoad:
      return "load";
    case ErrorMetric::kPosition:
      return "position";
  }
  return "unknown";
}

double RunResult::RmsError(ErrorMetric metric) const {
  switch (metric) {
    case ErrorMetric::kGraspForce:
      return errors.grasp_force_rms_n;
    case ErrorMetric::kLoad:
      return errors.load_rms_n;
    case ErrorMetric::kPosition:
      return errors.position_rms_m;
  }
  return 0;
}

rig::Result<SceneResult> SweepScene(const proto::Scenario& spec, const std::string& spec_directory,
                                    const SweepOptions& options, const RunControl& control) {
  proto::Scenario base = spec;
  base.mutable_models()->set_noise(proto::NOISE_OFF);
  const std::optional<double> duration_s =
      options.duration_s ? options.duration_s
                         : (options.quick ? std::optional<double>(kQuickDurationS) : std::nullopt);
  if (duration_s) {
    if (!(*duration_s > 0) || !std::isfinite(*duration_s)) {
      return rig::MakeError("duration must be a positive number of seconds");
    }
    base = TruncatedTo(std::move(base), std::min(*duration_s, spec.simulation().duration_s()));
  }
  const PlannedRun reference{RunKind::kReference, ReferenceFidelity(options.quick)};
  const proto::Scenario reference_spec = WithFidelity(base, reference.fidelity);
  auto reference_config = ResolveChecked(reference_spec, spec_directory, std::nullopt);
  if (!reference_config) return reference_config.error();
  if (options.progress != nullptr && reference_config.value().hall_sensors.tactile_enabled) {
    *options.progress << spec.name() << ": the DUT's calibration at the reference field ("
                      << reference.fidelity.field_fidelity
                      << "; once per build, then read from the cache)" << std::endl;
  }
  if (auto set_up = SetUpTactile(reference_spec, reference_config.value(), options.film_models,
                                 options.calibrations, control.stop_requested);
      !set_up) {
    return rig::InContext(spec.name() + ": ", set_up.error());
  }
  const ScenarioConfig& ref_config = reference_config.value();
  const CapturedRun reference_run = RunCaptured(ref_config, control);
  if (!RunCompleted(reference_run.report)) {
    return StoppedShortError(spec.name() + ": the reference run stopped short: ",
                             reference_run.report);
  }
  SceneResult scene;
  scene.scene = spec.name();
  if (duration_s.value_or(spec.simulation().duration_s()) < spec.simulation().duration_s()) {
    scene.cut_to_s = duration_s;
  }
  scene.runs.push_back(Evaluate(reference, ref_config, reference_run, reference_run.trace));
  scene.tolerance = options.tolerance;
  std::vector<ScenarioConfig> configs{ref_config};
  const bool has_film = spec.models().tactile().enabled();
  scene.tightest_force_envelope_n = TightestForceEnvelopeN(spec);
  const std::vector<SensorEffect> effects =
      has_film ? SweptEffects(spec) : std::vector<SensorEffect>{};
  for (const PlannedRun& planned :
       PlanSweep(SceneFidelity(spec), has_film, options.quick, effects)) {
    if (Interrupted(control)) return rig::MakeError(rig::ErrorCode::kInterrupted, "interrupted");
    auto config = ResolveWithCalibration(WithFidelity(base, planned.fidelity), spec_directory,
                                         ref_config.seed, ref_config.hall_sensors.calibration);
    if (!config) return config.error();
    // One model per level for the whole sweep when the caller gives film_models: no run or timing
    // repeat tabulates a map again.
    if (auto built = BuildFilmField(config.value(), options.film_models, control.stop_requested);
        !built) {
      return built.error();
    }
    const CapturedRun run = RunCaptured(config.value(), control);
    scene.runs.push_back(Evaluate(planned, config.value(), run, reference_run.trace));
    configs.push_back(std::move(config).value());
    if (options.progress != nullptr) {
      *options.progress << scene.scene << ": " << RunKindName(planned.kind) << " "
                        << FidelityLabel(planned.fidelity) << ": "
                        << rig::NumberText(scene.runs.back().wall_s_per_sim_s) << " s/sim s"
                        << std::endl;
    }
  }
  if (options.progress != nullptr && options.timing_repeats > 1) {
    *options.progress << scene.scene << ": timing the runs under "
                      << rig::NumberText(options.cheap_run_wall_s) << " s "
                      << options.timing_repeats << " more times, in rounds" << std::endl;
  }
  TimeInRounds(configs, scene, options, control);
  MarkParetoFronts(scene);
  auto shipped =
      RunDefaultAsShipped(spec, spec_directory, control, options.calibrations, options.film_models);
  if (!shipped) return shipped.error();
  scene.shipped = std::move(shipped).value();
  return scene;
}

rig::Result<ShippedVerdict> RunDefaultAsShipped(const proto::Scenario& spec,
                                                const std::string& spec_directory,
                                                const RunControl& control,
                                                const FileCalibrationStore* calibrations,
                                                FilmFieldModels* film_models) {
  RunRequest request;
  request.spec = &spec;
  request.spec_directory = spec_directory;
  request.dut_factory = control.dut_factory;
  request.film_models = film_models;
  request.calibrations = calibrations;
  RunPipelineResult run = RunPipeline(
      request, {control.wall_clock, control.realtime_clock, control.stop_requested, nullptr});
  if (const RunError* error = std::get_if<RunError>(&run)) {
    return rig::MakeError(error->failure == RunFailure::kInterrupted ? rig::ErrorCode::kInterrupted
                                                                     : rig::ErrorCode::kUnspecified,
                          error->message);
  }
  const proto::Report& report = std::get<RunOutcome>(run).report;
  ShippedVerdict verdict;
  verdict.passed = report.passed();
  verdict.stop_reason = report.stop_reason();
  for (const proto::EnvelopeResult& envelope : report.envelopes()) {
    if (!envelope.meets_expectation()) verdict.missed.push_back(envelope.name());
  }
  return verdict;
}

std::vector<std::size_t> ParetoFront(const std::vector<RunResult>& runs,
                                     std::span<const ErrorMetric> metrics,
                                     const ParetoTolerance& tolerance) {
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunResult& run = runs[i];
    if (run.run.kind == RunKind::kReference || run.run.kind == RunKind::kEffect) continue;
    if (!run.errors.complete() || !std::isfinite(run.wall_s_per_sim_s)) continue;
    if (std::any_of(metrics.begin(), metrics.end(),
                    [&](ErrorMetric metric) { return !std::isfinite(run.RmsError(metric)); })) {
      continue;
    }
    candidates.push_back(i);
  }
  const double faster = 1 - tolerance.timing_margin, slower = 1 + tolerance.timing_margin;
  const double better = 1 - tolerance.error_tolerance, worse = 1 + tolerance.error_tolerance;
  // a dominates b: no worse than b in time and in every error (within the tolerances), and clearly
  // better in one of them.
  const auto dominates = [&](std::size_t a, std::size_t b) {
    const double ta = runs[a].wall_s_per_sim_s, tb = runs[b].wall_s_per_sim_s;
    bool no_worse = ta <= tb * slower, clearly_better = ta < tb * faster;
    for (ErrorMetric metric : metrics) {
      const double ea = runs[a].RmsError(metric), eb = runs[b].RmsError(metric);
      no_worse = no_worse && (ea <= eb * worse || ea - eb <= tolerance.error_floor);
      clearly_better = clearly_better || (ea < eb * better && eb - ea > tolerance.error_floor);
    }
    return no_worse && clearly_better;
  };
  std::vector<std::size_t> front;
  for (std::size_t b : candidates) {
    if (std::none_of(candidates.begin(), candidates.end(),
                     [&](std::size_t a) { return dominates(a, b); })) {
      front.push_back(b);
    }
  }
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
    return runs[a].wall_s_per_sim_s < runs[b].wall_s_per_sim_s;
  });
  return front;
}

std::vector<std::size_t> ParetoFront(const std::vector<RunResult>& runs, ErrorMetric metric,
                                     const ParetoTolerance& tolerance) {
  return ParetoFront(runs, std::span<const ErrorMetric>(&metric, 1), tolerance);
}

void MarkParetoFronts(SceneResult& scene) {
  for (RunResult& run : scene.runs) {
    run.pareto.clear();
    run.on_joint_front = false;
  }
  for (ErrorMetric metric : kErrorMetrics) {
    for (std::size_t index : ParetoFront(scene.runs, metric, scene.tolerance)) {
      scene.runs[index].pareto.push_back(metric);
    }
  }
  for (std::size_t index : ParetoFront(scene.runs, kErrorMetrics, scene.tolerance)) {
    scene.runs[index].on_joint_front = true;
  }
}

std::string WorkPrecisionCsv(const std::vector<SceneResult>& scenes) {
  std::string out =
      "scene,kind,integrator,plant_substeps,step_s,field_fidelity,wall_s_per_sim_s,"
      "real_time_factor,grasp_force_rms_error_n,grasp_force_max_error_n,load_rms_error_n,"
      "position_rms_error_m,position_max_error_m,passes_envelopes,pareto,load_max_error_n,"
      "samples_compared,samples_missing,timing_runs,stop_reason,effect_off\n";
  for (const SceneResult& scene : scenes) {
    for (const RunResult& run : scene.runs) {
      const ErrorMetrics& e = run.errors;
      const std::vector<std::string> fields = {
          scene.scene,
          RunKindName(run.run.kind),
          IntegratorLabel(run.run.fidelity),
          std::to_string(run.run.fidelity.plant_substeps),
          rig::NumberText(run.step_s),
          run.run.fidelity.field_fidelity,
          rig::NumberText(run.wall_s_per_sim_s),
          RealTimeFactor(run.wall_s_per_sim_s),
          rig::NumberText(e.grasp_force_rms_n),
          rig::NumberText(e.grasp_force_max_n),
          rig::NumberText(e.load_rms_n),
          rig::NumberText(e.position_rms_m),
          rig::NumberText(e.position_max_m),
          run.passes_envelopes ? "true" : "false",
          ParetoField(run),
          rig::NumberText(e.load_max_n),
          std::to_string(e.samples_compared),
          std::to_string(e.samples_missing),
          std::to_string(run.timing_runs),
          run.stop_reason,
          run.run.fidelity.effect_off ? SensorEffectName(*run.run.fidelity.effect_off) : ""};
      for (std::size_t i = 0; i < fields.size(); ++i) {
        out.append(i > 0 ? "," : "").append(CsvField(fields[i]));
      }
      out += "\n";
    }
  }
  return out;
}

std::vector<ScatterPlot> WorkPrecisionPlots(const std::vector<SceneResult>& scenes) {
  std::vector<ScatterPlot> plots;
  for (const SceneResult& scene : scenes) {
    for (ErrorMetric metric : kErrorMetrics) plots.push_back(PlotFor(scene, metric));
  }
  return plots;
}

const RunResult* CheapestPassingFrontRun(const SceneResult& scene) {
  const RunResult* cheapest = nullptr;
  for (const RunResult& run : scene.runs) {
    if (!run.on_joint_front || !run.passes_envelopes) continue;
    if (cheapest == nullptr || run.wall_s_per_sim_s < cheapest->wall_s_per_sim_s) cheapest = &run;
  }
  return cheapest;
}

std::vector<SensorEffect> SweptEffects(const proto::Scenario& spec) {
  const proto::Tactile& tactile = spec.models().tactile();
  std::vector<SensorEffect> effects;
  for (SensorEffect effect : kSensorEffects) {
    if (effect == SensorEffect::kChipNoise) continue;  // off in every noise-free run
    if (EffectOn(tactile, effect)) effects.push_back(effect);
  }
  return effects;
}

double TightestForceEnvelopeN(const proto::Scenario& spec) {
  double tightest = std::numeric_limits<double>::quiet_NaN();
  for (const proto::Envelope& envelope : spec.envelopes()) {
    if (envelope.expect() == proto::FAIL) continue;
    if (!IsForceSignal(envelope.signal())) continue;
    if (!envelope.has_lower() && !envelope.has_upper()) continue;
    const double width = envelope.has_lower() && envelope.has_upper()
                             ? envelope.upper() - envelope.lower()
                             : std::abs(envelope.has_upper() ? envelope.upper() : envelope.lower());
    if (!(width >= tightest)) tightest = width;  // also replaces the NaN start
  }
  return tightest;
}

std::string EffectTable(const SceneResult& scene) {
  const RunResult* base = DefaultRun(scene);
  std::vector<const RunResult*> effect_runs;
  for (const RunResult& run : scene.runs) {
    if (run.run.kind == RunKind::kEffect) effect_runs.push_back(&run);
  }
  if (effect_runs.empty() || base == nullptr) return "";
  const double allowed_n = kEffectDropFraction * scene.tightest_force_envelope_n;
  std::string out =
      scene.scene + ": each sensor effect switched off (noise-free); may drop: adds <= " +
      rig::NumberText(kEffectDropFraction * 100) + " % of the tightest force envelope (";
  out += std::isfinite(allowed_n) ? rig::NumberText(scene.tightest_force_envelope_n) + " N)\n"
                                  : "none)\n";
  char line[256];
  std::snprintf(line, sizeof(line), "  %-20s %-12s %-12s %-12s %-12s %-12s %-10s %s\n",
                "effect off", "grasp err N", "load err N", "adds N", "moves chk N", "time/default",
                "envelopes", "drop?");
  out += line;
  const auto added = [&](const RunResult& run, ErrorMetric metric) {
    const double off = run.RmsError(metric), shipped = base->RmsError(metric);
    return std::sqrt(std::max(0.0, off * off - shipped * shipped));
  };
  const auto moved = [&](const RunResult& run) {
    double largest_n = 0;
    for (const auto& [name, worst_n] : run.force_check_worst_n) {
      for (const auto& [base_name, base_worst_n] : base->force_check_worst_n) {
        if (name == base_name) largest_n = std::max(largest_n, std::abs(worst_n - base_worst_n));
      }
    }
    return largest_n;
  };
  for (const RunResult* run : effect_runs) {
    const double adds_n =
        std::max(added(*run, ErrorMetric::kGraspForce), added(*run, ErrorMetric::kLoad));
    const double moves_n = moved(*run);
    // A failure the default shares (a check cut off by --quick) says nothing about the effect.
    const bool fails_alone = !run->passes_envelopes && base->passes_envelopes;
    const char* verdict = !std::isfinite(allowed_n)                ? "no force envelope"
                          : fails_alone                            ? "no (fails)"
                          : std::max(adds_n, moves_n) <= allowed_n ? "yes"
                                                                   : "no";
    std::snprintf(line, sizeof(line), "  %-20s %-12.3g %-12.3g %-12.3g %-12.3g %-12.3g %-10s %s\n",
                  SensorEffectName(*run->run.fidelity.effect_off),
                  run->RmsError(ErrorMetric::kGraspForce), run->RmsError(ErrorMetric::kLoad),
                  adds_n, moves_n, run->wall_s_per_sim_s / base->wall_s_per_sim_s,
                  run->passes_envelopes ? "pass" : "FAIL", verdict);
    out += line;
  }
  return out;
}

std::string FormatParetoTables(const SceneResult& scene) {
  std::string out;
  for (ErrorMetric metric : kErrorMetrics) out += FrontTable(scene, metric) + "\n";
  out += DefaultVerdict(scene);
  const std::string effects = EffectTable(scene);
  return effects.empty() ? out : out + "\n" + effects;
}

}  // namespace hilrig::host
