#include "host/sweep/sweep_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>

#include "host/scenario/field_path.h"
#include "host/scenario/field_problems.h"
#include "host/scenario/scenario_loader.h"
#include "host/scenario/spec_limits.h"
#include "host/scenario/text_spec.h"
#include "host/sweep/sweep_cases.h"
#include "host/sweep/sweep_statistics.h"
#include "rig/file_io.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr std::uint32_t kMaxSeeds = 1'000'000;
constexpr std::uint32_t kMaxAxisValues = 10'000;

bool Finite(double value) { return std::isfinite(value); }

void CheckSeeds(const proto::Seeds& seeds, const ProblemList& problems) {
  if (seeds.has_count() && seeds.list_size() > 0) {
    problems.AddHere("give a count or a list of seeds, not both");
  }
  if (seeds.has_count() && (seeds.count() == 0 || seeds.count() > kMaxSeeds)) {
    problems.Add("count", "must be in 1.." + std::to_string(kMaxSeeds));
  }
  if (seeds.has_first() && seeds.list_size() > 0) problems.Add("first", "goes with count only");
  if (seeds.list_size() > int(kMaxSeeds)) problems.Add("list", "more than a million seeds");
  std::set<std::uint64_t> seen;
  for (int i = 0; i < seeds.list_size(); ++i) {
    if (!seen.insert(seeds.list(i)).second) {
      problems.Element("list", i).AddHere("seed " + std::to_string(seeds.list(i)) + " again");
    }
  }
}

void CheckGrid(const proto::Grid& grid, const ProblemList& problems) {
  if (!grid.has_from() || !Finite(grid.from())) problems.Add("from", "a finite number is required");
  if (!grid.has_to() || !Finite(grid.to())) problems.Add("to", "a finite number is required");
  if (!grid.has_count() || grid.count() == 0 || grid.count() > kMaxAxisValues) {
    problems.Add("count", "must be in 1.." + std::to_string(kMaxAxisValues));
  }
  if (Finite(grid.from()) && Finite(grid.to()) && !Finite(grid.to() - grid.from())) {
    // Points between such ends are computed as from + t (to - from): the span must be a number.
    problems.AddHere("from and to are too far apart: to - from is not a finite number");
  }
  if (grid.log() && !(grid.from() > 0 && grid.to() > 0)) {
    problems.AddHere("a log grid needs from and to above 0");
  }
}

// low < high, both finite, both given.
void CheckRange(bool has_low, double low, bool has_high, double high, const ProblemList& problems) {
  if (!has_low || !Finite(low)) problems.Add("low", "a finite number is required");
  if (!has_high || !Finite(high)) problems.Add("high", "a finite number is required");
  if (has_low && has_high && !(low < high)) problems.AddHere("low must be below high");
}

void CheckDistribution(const proto::Distribution& distribution, const ProblemList& problems) {
  switch (distribution.kind_case()) {
    case proto::Distribution::kUniform: {
      const auto& uniform = distribution.uniform();
      CheckRange(uniform.has_low(), uniform.low(), uniform.has_high(), uniform.high(),
                 problems.Nested("uniform"));
      return;
    }
    case proto::Distribution::kLogUniform: {
      const auto& log_uniform = distribution.log_uniform();
      const ProblemList here = problems.Nested("log_uniform");
      CheckRange(log_uniform.has_low(), log_uniform.low(), log_uniform.has_high(),
                 log_uniform.high(), here);
      if (log_uniform.has_low() && !(log_uniform.low() > 0)) here.Add("low", "must be above 0");
      return;
    }
    case proto::Distribution::kNormal: {
      const auto& normal = distribution.normal();
      const ProblemList here = problems.Nested("normal");
      if (!normal.has_mean() || !Finite(normal.mean())) {
        here.Add("mean", "a finite number is required");
      }
      if (!normal.has_sigma() || !Finite(normal.sigma()) || !(normal.sigma() > 0)) {
        here.Add("sigma", "a finite number above 0 is required");
      }
      if (normal.has_low() && normal.has_high() && !(normal.low() < normal.high())) {
        here.AddHere("low must be below high");
      }
      // Truncation redraws; a window the normal almost never hits would redraw for ever.
      if (auto problem = TruncatedNormalProblem(normal)) here.AddHere(*problem);
      return;
    }
    case proto::Distribution::KIND_NOT_SET:
      problems.AddHere("uniform, normal or log_uniform is required");
      return;
  }
}

// What is wrong with setting `path` to `value` in every case of `sweep`, or nothing.
std::optional<std::string> SetProblem(const proto::Sweep& sweep,
                                      const std::vector<SweepScenario>& scenarios,
                                      const std::string& path, double value) {
  if (path.empty()) return "a path is required";
  if (path == "seed") return "the seed is swept by `seeds`, not set";
  for (const proto::Axis& axis : sweep.axis()) {
    if (axis.path() == path) return "\"" + path + "\" is swept by an axis, which would undo it";
  }
  if (!Finite(value)) return "the value of " + path + " is not a finite number";
  for (const SweepScenario& scenario : scenarios) {
    if (auto checked = CheckNumberPath(scenario.spec, path); !checked.ok()) {
      return "in " + scenario.path + ": " + checked.error().message;
    }
  }
  return std::nullopt;
}

void CheckSets(const proto::Sweep& sweep, const std::vector<SweepScenario>& scenarios,
               const ProblemList& root) {
  for (int i = 0; i < sweep.set_size(); ++i) {
    const proto::SweepSet& set = sweep.set(i);
    if (auto problem = SetProblem(sweep, scenarios, set.path(), set.value())) {
      root.Element("set", i).AddHere(std::move(*problem));
    }
  }
}

void CheckAxes(const proto::Sweep& sweep, const std::vector<SweepScenario>& scenarios,
               const ProblemList& root) {
  std::set<std::string> paths;
  for (int i = 0; i < sweep.axis_size(); ++i) {
    const proto::Axis& axis = sweep.axis(i);
    const ProblemList here = root.Element("axis", i);
    if (axis.path().empty()) {
      here.AddHere("path is required");
    } else if (axis.path() == "seed") {
      here.Add("path", "the seed is swept by `seeds`, not by an axis");
    } else if (!paths.insert(axis.path()).second) {
      here.Add("path", "\"" + axis.path() + "\" is swept by an earlier axis");
    } else {
      for (const SweepScenario& scenario : scenarios) {
        if (auto checked = CheckNumberPath(scenario.spec, axis.path()); !checked.ok()) {
          here.Add("path", "in " + scenario.path + ": " + checked.error().message);
        }
      }
    }
    switch (axis.values_case()) {
      case proto::Axis::kList:
        if (axis.list().value_size() == 0 || axis.list().value_size() > int(kMaxAxisValues)) {
          here.Nested("list").Add("value", "1.." + std::to_string(kMaxAxisValues) + " values");
        }
        for (int v = 0; v < axis.list().value_size(); ++v) {
          if (!Finite(axis.list().value(v))) {
            here.Nested("list").Element("value", v).AddHere("not a finite number");
          }
        }
        break;
      case proto::Axis::kGrid:
        CheckGrid(axis.grid(), here.Nested("grid"));
        break;
      case proto::Axis::kDistribution:
        CheckDistribution(axis.distribution(), here.Nested("distribution"));
        break;
      case proto::Axis::VALUES_NOT_SET:
        here.AddHere("list, grid or distribution is required");
        break;
    }
  }
}

// The names a criterion may refer to: every scenario's name, and every envelope of each. A margin
// criterion must name an envelope expected to pass: an ablation's margin is negative by design.
void CheckCriteria(const proto::Sweep& sweep, const std::vector<SweepScenario>& scenarios,
                   const ProblemList& root) {
  if (sweep.criterion_size() == 0) root.AddHere("at least one criterion is required");
  for (int i = 0; i < sweep.criterion_size(); ++i) {
    const proto::Criterion& criterion = sweep.criterion(i);
    const ProblemList here = root.Element("criterion", i);
    bool scenario_found = criterion.scenario().empty();
    bool any_named = false;
    bool margin_graded = false;  // a named envelope is expected to pass, so it has room to grade
    for (const SweepScenario& scenario : scenarios) {
      if (!criterion.scenario().empty() && scenario.spec.name() != criterion.scenario()) continue;
      scenario_found = true;
      for (const proto::Envelope& envelope : scenario.spec.envelopes()) {
        if (!criterion.envelope().empty() && envelope.name() != criterion.envelope()) continue;
        any_named = true;
        margin_graded = margin_graded || envelope.expect() != proto::FAIL;
      }
    }
    const bool envelope_found = criterion.envelope().empty() || any_named;
    if (!scenario_found) {
      here.Add("scenario", "no scenario of the sweep is named \"" + criterion.scenario() + "\"");
    } else if (!envelope_found) {
      here.Add("envelope",
               "no envelope \"" + criterion.envelope() + "\" in " +
                   (criterion.scenario().empty() ? "the sweep's scenarios" : criterion.scenario()));
    } else if (criterion.has_quantile() && any_named && !margin_graded) {
      here.Add("quantile",
               "every envelope the criterion names is expected to fail (expect: FAIL), so its "
               "margin is negative by design; grade an ablation with min_pass_rate");
    }
    if (!criterion.has_min_pass_rate() && !criterion.has_quantile()) {
      here.AddHere("set min_pass_rate, quantile or both");
    }
    if (criterion.has_min_pass_rate() &&
        !(criterion.min_pass_rate() >= 0 && criterion.min_pass_rate() <= 1)) {
      here.Add("min_pass_rate", "must be in [0, 1]");
    }
    if (criterion.has_confidence() && !(criterion.confidence() > 0 && criterion.confidence() < 1)) {
      here.Add("confidence", "must be in (0, 1)");
    }
    if (criterion.has_confidence() && !criterion.has_min_pass_rate()) {
      here.Add("confidence", "goes with min_pass_rate");
    }
    if (criterion.has_quantile() && !(criterion.quantile() >= 0 && criterion.quantile() <= 1)) {
      here.Add("quantile", "must be in [0, 1]");
    }
    if (criterion.has_min_margin() && !Finite(criterion.min_margin())) {
      here.Add("min_margin", "not a finite number");
    }
    if (criterion.has_min_margin() && !criterion.has_quantile()) {
      here.Add("min_margin", "goes with quantile");
    }
  }
}

// Loads every scenario the sweep names; a scenario that does not load is a problem at its entry,
// with the scenario's own located problems.
std::vector<SweepScenario> LoadScenarios(const proto::Sweep& sweep, const std::string& folder,
                                         const ProblemList& root) {
  std::vector<SweepScenario> scenarios;
  std::set<std::string> names;
  if (sweep.scenario_size() == 0) root.AddHere("at least one scenario is required");
  for (int i = 0; i < sweep.scenario_size(); ++i) {
    const std::filesystem::path name(sweep.scenario(i));
    const std::string path =
        name.is_absolute() ? name.string() : (std::filesystem::path(folder) / name).string();
    auto loaded = LoadScenario(path);
    if (!loaded) {
      root.Element("scenario", i).AddHere("does not load:\n" + loaded.error().message);
      continue;
    }
    if (!names.insert(loaded.value().name()).second) {
      root.Element("scenario", i)
          .AddHere("a second scenario named \"" + loaded.value().name() + "\"");
      continue;
    }
    scenarios.push_back({path, std::move(loaded).value()});
  }
  return scenarios;
}

// The fewest cases whose all passing gives a Wilson lower bound of at least `min_pass_rate` at
// `confidence`, or nullopt when no sweep of at most kMaxSweepCases does (a rate of 1 never).
// O(log kMaxSweepCases): the bound of n of n grows with n.
std::optional<std::uint64_t> CasesNeeded(double min_pass_rate, double confidence) {
  const auto reaches = [&](std::uint64_t n) {
    return WilsonInterval(n, n, confidence).lower >= min_pass_rate;
  };
  if (!reaches(kMaxSweepCases)) return std::nullopt;
  std::uint64_t low = 0, high = kMaxSweepCases;  // reaches(high), not reaches(low)
  while (high - low > 1) {
    const std::uint64_t middle = low + (high - low) / 2;
    (reaches(middle) ? high : low) = middle;
  }
  return high;
}

// A pass-rate criterion that a scenario's cases could not meet even if every one passed: the
// sweep would run for hours to a verdict known now. Every scenario of a sweep has the same cases.
void CheckPassRatesReachable(const proto::Sweep& sweep, const ProblemList& root) {
  const auto per_scenario =
      static_cast<std::uint64_t>(CaseCountEstimate(sweep) / std::max(1, sweep.scenario_size()));
  for (int i = 0; i < sweep.criterion_size(); ++i) {
    const proto::Criterion& criterion = sweep.criterion(i);
    if (!criterion.has_min_pass_rate()) continue;
    const double confidence =
        criterion.has_confidence() ? criterion.confidence() : kDefaultPassRateConfidence;
    const double best = WilsonInterval(per_scenario, per_scenario, confidence).lower;
    if (best >= criterion.min_pass_rate()) continue;
    const std::optional<std::uint64_t> needed = CasesNeeded(criterion.min_pass_rate(), confidence);
    root.Element("criterion", i)
        .Add("min_pass_rate",
             "cannot be met: with all " + std::to_string(per_scenario) +
                 " cases of a scenario passing, the pass rate's lower bound at " +
                 rig::NumberText(confidence) + " confidence is " + rig::NumberText(best) +
                 (needed ? "; it needs at least " + std::to_string(*needed) + " cases per scenario"
                         : "; no number of cases reaches it"));
  }
}

std::vector<FieldProblem> ValidateSweep(const proto::Sweep& sweep, const std::string& folder,
                                        std::vector<SweepScenario>& scenarios) {
  std::vector<FieldProblem> problems;
  const ProblemList root(problems);
  if (sweep.name().empty()) {
    root.AddHere("name is required");
  } else if (auto problem = NameCharacterProblem(sweep.name())) {
    root.Add("name", std::move(*problem));
  }
  // Paths and names reach failing.txt, the batch scripts and the terminal.
  CheckEveryScalar(sweep, root, ControlCharacterProblem);
  scenarios = LoadScenarios(sweep, folder, root);
  if (sweep.has_seeds()) CheckSeeds(sweep.seeds(), root.Nested("seeds"));
  CheckAxes(sweep, scenarios, root);
  CheckSets(sweep, scenarios, root);
  CheckCriteria(sweep, scenarios, root);
  if (problems.empty()) {
    const double cases = CaseCountEstimate(sweep);
    if (cases > double(kMaxSweepCases)) {
      root.AddHere(rig::NumberText(cases) + " cases: at most " + std::to_string(kMaxSweepCases) +
                   " per sweep");
    } else {
      CheckPassRatesReachable(sweep, root);
    }
  }
  return problems;
}

}  // namespace

rig::Result<void> AddSweepSets(LoadedSweep& sweep,
                               const std::vector<std::pair<std::string, double>>& sets) {
  for (const auto& [path, value] : sets) {
    if (auto problem = SetProblem(sweep.spec, sweep.scenarios, path, value)) {
      return rig::MakeError("--set " + path + ": " + *problem);
    }
  }
  for (const auto& [path, value] : sets) {
    proto::SweepSet* set = sweep.spec.add_set();
    set->set_path(path);
    set->set_value(value);
  }
  return {};
}

rig::Result<LoadedSweep> ParseSweep(const std::string& text, const std::string& file_label,
                                    const std::string& folder) {
  LoadedSweep sweep;
  sweep.file = file_label;
  auto parsed = ParseTextSpec(text, file_label, sweep.spec, [&](const google::protobuf::Message&) {
    return ValidateSweep(sweep.spec, folder, sweep.scenarios);
  });
  if (!parsed.ok()) return parsed.error();
  return sweep;
}

rig::Result<LoadedSweep> LoadSweep(const std::string& path) {
  auto text = rig::ReadRegularFile(path, kMaxScenarioFileBytes);
  if (!text) return text.error();
  return ParseSweep(text.value(), path, std::filesystem::path(path).parent_path().string());
}

}  // namespace hilrig::host
