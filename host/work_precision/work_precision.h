// The work-precision benchmark: what each plant integrator, step size and film field fidelity
// costs in wall time per simulated second, and how much error it buys against a tight reference
// run of the same scene (host/fidelity/). Every run of a scene shares one DUT calibration and runs
// noise-free, so the differences between runs are the models' and the integrators' only. The
// sweep, its Pareto fronts, CSV and plots are `hilrig bench`'s. Nothing here reads a clock: the
// wall clock comes in with RunControl.
#pragma once

#include <limits>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "host/cache/calibration_store.h"
#include "host/fidelity/fidelity_choice.h"
#include "host/fidelity/reference_run.h"
#include "host/fidelity/trace_comparison.h"
#include "host/report/scatter_plot.h"
#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/sensors/tactile/sensor_effect.h"
#include "proto/report.pb.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// ---------------------------------------------------------------------------------------------
// The sweep.

// kEffect: the scene's own fidelity with one tactile forward-model effect switched off; such runs
// answer whether a scene could leave the effect out (EffectTable), and stay off the Pareto fronts,
// which choose among integrators and field levels of one model.
enum class RunKind { kReference, kIntegrator, kField, kDefault, kEffect };

// "reference", "integrator", "field", "default", "effect"
std::string RunKindName(RunKind kind);

struct PlannedRun {
  RunKind kind = RunKind::kIntegrator;
  FidelityChoice fidelity;
};

// Every run of one scene after the reference: integrators x step sizes at the scene's field
// fidelity, field fidelities at the scene's integrator and step (only when the scene has a film
// field to vary: `has_film`), each of `effects` switched off at the scene's own fidelity, and the
// scene as shipped, last. A configuration is planned once: the sweep's point that is the scene's
// own configuration is its `default` run, so that one configuration is never timed twice and then
// split by timing noise.
std::vector<PlannedRun> PlanSweep(const FidelityChoice& scene, bool has_film, bool quick,
                                  std::span<const SensorEffect> effects = {});

// The effects a sweep of `spec` switches off one at a time: those on in the scene (its switch, or
// the default), except the chip's noise, which the sweep's noise-free runs have off already.
std::vector<SensorEffect> SweptEffects(const proto::Scenario& spec);

// The narrowest allowed range of the spec's force envelopes (signals in N) that expect a pass:
// upper - lower, or the one limit's magnitude when only one is set (an error bound). NaN when the
// spec has none.
double TightestForceEnvelopeN(const proto::Scenario& spec);

// A scene may leave an effect out when switching it off adds at most this fraction of its
// tightest force envelope to the force errors, moves none of its force checks by more, and the run
// passes its envelopes wherever the default passes them.
inline constexpr double kEffectDropFraction = 0.05;

enum class ErrorMetric { kGraspForce, kLoad, kPosition };
inline constexpr ErrorMetric kErrorMetrics[] = {ErrorMetric::kGraspForce, ErrorMetric::kLoad,
                                                ErrorMetric::kPosition};
std::string MetricName(ErrorMetric metric);  // "grasp_force", "load", "position"

struct RunResult {
  PlannedRun run;
  double step_s = 0;            // the plant's integration step
  double wall_s_per_sim_s = 0;  // fastest of the timing runs, stepping loop only
  double simulated_s = 0;
  int timing_runs = 0;
  ErrorMetrics errors;
  bool passes_envelopes = false;
  // The worst value of each force check (an envelope on a signal in N that expects a pass and saw
  // samples), by name: what the run's own DUT estimates did, which the errors against the
  // reference (true forces only) do not show.
  std::vector<std::pair<std::string, double>> force_check_worst_n;
  std::string stop_reason;
  std::vector<ErrorMetric> pareto;  // the metrics on whose single-error front this run lies
  // On the front of time against all three errors at once: no other run is as fast and as
  // accurate in every error (within the tolerance) and clearly better in one of them.
  bool on_joint_front = false;

  double RmsError(ErrorMetric metric) const;
};

// How far apart two runs must be to count as different on the front. Wall times of equal work
// vary by 10-20 % on a shared machine, and errors that agree to a percent are the same model
// error, so a run dominates another only when it is faster by more than `timing_margin` at no
// more than (1 + error_tolerance) of its error, or more accurate by more than `error_tolerance`
// at no more than (1 + timing_margin) of its time. Two errors closer than `error_floor` (N or m)
// are equal whatever their ratio: trace.csv keeps 9 significant digits of signals of order 1 N
// and 1 m, so a difference below 1e-9 is below what the rig records (a burst balloon's load error
// is 2e-33 N in one run and 1.6e-33 N in another: rounding, not a model that is 30 % better).
struct ParetoTolerance {
  double timing_margin = 0.15;
  double error_tolerance = 0.02;
  double error_floor = 1e-9;
};

// The default run as `hilrig run` makes it: the spec's own noise and seed, calibrated on its own
// field level. The sweep's runs are noise-free so that they differ only in their models, and a
// scene whose outcome turns on a knife edge can meet its verdicts without noise and miss them with
// it.
struct ShippedVerdict {
  bool passed = false;
  std::vector<std::string> missed;  // envelopes whose verdict was not the expected one
  std::string stop_reason;
};

struct SceneResult {
  std::string scene;
  std::vector<RunResult> runs;  // runs[0] is the reference
  ParetoTolerance tolerance;
  ShippedVerdict shipped;
  // Set when the sweep's runs were cut short of the scene (--quick, --duration-s): their
  // envelope verdicts then cover only this much, and a check whose window starts later fails
  // for having nothing to judge.
  std::optional<double> cut_to_s;
  double tightest_force_envelope_n = std::numeric_limits<double>::quiet_NaN();
};

// The default as shipped, for the whole scene even when the sweep cuts its runs short (a check
// whose window lies past the cut has nothing to judge). One run: it costs what `hilrig run` does.
rig::Result<ShippedVerdict> RunDefaultAsShipped(const proto::Scenario& spec,
                                                const std::string& spec_directory,
                                                const RunControl& control,
                                                const FileCalibrationStore* calibrations = nullptr,
                                                FilmFieldModels* film_models = nullptr);

struct SweepOptions {
  bool quick = false;
  std::optional<double> duration_s;  // cut every run of the scene to this; --quick: 3 s
  // Runs cheaper than cheap_run_wall_s are timed this often more without sinks, in rounds over
  // the scene's runs (fastest kept); <= 1: every run is timed by its captured run alone.
  int timing_repeats = 20;
  ParetoTolerance tolerance;
  double cheap_run_wall_s = 2.0;
  std::ostream* progress = nullptr;  // a line per run
  // The on-disk setup caches (null: none). The reference calibration at tiles:64 takes about 47 s
  // per tactile scene, the same in every sweep of one build.
  const FileCalibrationStore* calibrations = nullptr;
  FilmFieldModels* film_models = nullptr;
};

// The whole sweep of one scene: calibration at the reference fidelity, the reference run, then
// PlanSweep's runs, all noise-free; fronts marked; then the default once more as shipped.
rig::Result<SceneResult> SweepScene(const proto::Scenario& spec, const std::string& spec_directory,
                                    const SweepOptions& options, const RunControl& control);

// Indices into `runs` of the non-dominated runs (lower time and lower error both better, within
// `tolerance`), excluding the reference and runs whose comparison is incomplete, sorted by time.
std::vector<std::size_t> ParetoFront(const std::vector<RunResult>& runs, ErrorMetric metric,
                                     const ParetoTolerance& tolerance = {});

// The same over several errors at once (the joint front): a run dominates another when it is no
// slower and no less accurate in any of `metrics` (within `tolerance`) and clearly better in one.
std::vector<std::size_t> ParetoFront(const std::vector<RunResult>& runs,
                                     std::span<const ErrorMetric> metrics,
                                     const ParetoTolerance& tolerance = {});

// Sets RunResult::pareto from ParetoFront for every metric, and on_joint_front.
void MarkParetoFronts(SceneResult& scene);

// The run a scene should default to: the cheapest (least wall time per simulated second) of the
// runs on the joint front that pass their envelopes, or null if none does. Cheaper runs off the
// front are beaten by one about as fast and more accurate; cheaper ones that fail are not an
// option. Needs MarkParetoFronts first.
const RunResult* CheapestPassingFrontRun(const SceneResult& scene);

// The CSV, header first, one row per run of every scene.
std::string WorkPrecisionCsv(const std::vector<SceneResult>& scenes);

// One log-log panel per scene and metric: error against wall time per simulated second.
std::vector<ScatterPlot> WorkPrecisionPlots(const std::vector<SceneResult>& scenes);

// What switching each effect off did (the kEffect runs): its force errors, the error it adds to
// the default's, sqrt(max(0, e_off^2 - e_default^2)) for the larger of grasp force and load, how
// far it moves the scene's force checks (the largest change of a check's worst value against the
// default's), the time against the default's, and whether the scene could drop it: the larger of
// the two within kEffectDropFraction. Empty when the sweep had no effect runs.
std::string EffectTable(const SceneResult& scene);

// Per scene and metric, the front as a table; whether the scene's default is on it and passes its
// envelopes; the cheapest passing run on the joint front; and the EffectTable.
std::string FormatParetoTables(const SceneResult& scene);

}  // namespace hilrig::host
